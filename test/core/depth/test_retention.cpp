// keepLowestVariance against a direct definition: sort candidates by (variance, index) and keep the
// first keep_count. Sizes span several chunks so that the parallel passes and the per-chunk tie
// quotas are exercised, with heavy ties (as when most pixels have the prior variance), long runs of
// one variance (gathered as runs, whole blocks at once), values sharing the first radix digit,
// special values and the edge counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/retention.hpp"

namespace mm = multimodal_nvs;

namespace {

struct Field {
  std::vector<float> variance;
  std::vector<std::uint8_t> candidate;
};

// Variances drawn from few distinct values (ties) mixed with continuous ones.
Field randomField(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> continuous(0.0f, 10.0f);
  std::uniform_int_distribution<int> pick(0, 9);
  Field f;
  f.variance.resize(n);
  f.candidate.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int p = pick(rng);
    f.variance[i] = p < 5 ? 4.0f : (p < 6 ? 0.5f : continuous(rng));
    f.candidate[i] = p != 9;
  }
  return f;
}

std::vector<std::uint8_t> keptByDefinition(const Field& f, long long keep_count) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < f.variance.size(); ++i) {
    if (f.candidate[i]) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return f.variance[a] < f.variance[b]; });
  std::vector<std::uint8_t> kept(f.variance.size(), 0);
  const std::size_t count = std::min<std::size_t>(order.size(), std::max<long long>(0, keep_count));
  for (std::size_t k = 0; k < count; ++k)
    kept[order[k]] = 1;
  return kept;
}

// The ranking keepLowestVariance documents: the variance's bits as an unsigned integer (the value's
// order for finite values >= 0; +inf, NaN and negative values after them), then the index.
std::vector<std::uint8_t> keptByBits(const Field& f, long long keep_count) {
  const auto bits = [&](std::size_t i) {
    std::uint32_t b;
    std::memcpy(&b, &f.variance[i], sizeof b);
    return b;
  };
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < f.variance.size(); ++i) {
    if (f.candidate[i]) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return bits(a) < bits(b); });
  std::vector<std::uint8_t> kept(f.variance.size(), 0);
  const std::size_t count = std::min<std::size_t>(order.size(), std::max<long long>(0, keep_count));
  for (std::size_t k = 0; k < count; ++k)
    kept[order[k]] = 1;
  return kept;
}

// Every keep count of interest (the edges, and the positions of the distinct ranked keys, so that
// the threshold falls on every key at its first tie, inside its ties and at its last), serially
// and on pools of 1, 2, 3 and 8 threads.
void expectKeptByBits(const Field& f, std::vector<long long> keeps, const char* what) {
  const std::size_t n = f.variance.size();
  const long long candidates =
      std::count_if(f.candidate.begin(), f.candidate.end(), [](std::uint8_t c) { return c != 0; });
  for (long long k : {-1LL, 0LL, 1LL, candidates - 1, candidates, candidates + 1})
    keeps.push_back(k);
  std::vector<mm::ThreadPool*> pools{nullptr};
  std::vector<std::unique_ptr<mm::ThreadPool>> owned;
  for (int threads : {1, 2, 3, 8}) {
    owned.push_back(std::make_unique<mm::ThreadPool>(threads));
    pools.push_back(owned.back().get());
  }
  for (long long keep : keeps) {
    const std::vector<std::uint8_t> expected = keptByBits(f, keep);
    const long long expected_count = std::count(expected.begin(), expected.end(), 1);
    for (mm::ThreadPool* pool : pools) {
      std::vector<std::uint8_t> kept(n, 7);
      EXPECT_EQ(
          mm::keepLowestVariance(f.variance.data(), f.candidate.data(), n, keep, kept.data(), pool),
          expected_count)
          << what << ", keep " << keep;
      const auto diff = std::mismatch(kept.begin(), kept.end(), expected.begin()).first;
      EXPECT_TRUE(diff == kept.end())  // not EXPECT_EQ: it would print the whole images
          << what << ", keep " << keep << ", " << (pool ? pool->size() : 0)
          << " threads: first difference at pixel " << diff - kept.begin();
    }
  }
}

// Keep counts at the first, middle and last rank of some distinct keys.
std::vector<long long> keepsAtKeys(const Field& f, std::size_t max_keys) {
  std::vector<std::pair<std::uint32_t, std::size_t>> ranked;
  for (std::size_t i = 0; i < f.variance.size(); ++i) {
    std::uint32_t b;
    std::memcpy(&b, &f.variance[i], sizeof b);
    if (f.candidate[i]) ranked.emplace_back(b, i);
  }
  std::sort(ranked.begin(), ranked.end());
  std::vector<long long> keeps;
  std::size_t first = 0;
  for (std::size_t k = 1, keys = 0; k <= ranked.size() && keys < max_keys; ++k) {
    if (k < ranked.size() && ranked[k].first == ranked[first].first) continue;
    const long long begin = static_cast<long long>(first), end = static_cast<long long>(k);
    for (long long keep : {begin + 1, (begin + end + 1) / 2, end})
      keeps.push_back(keep);
    first = k;
    ++keys;
  }
  return keeps;
}

float floatOfBits(std::uint32_t b) {
  float v;
  std::memcpy(&v, &b, sizeof v);
  return v;
}

}  // namespace

TEST(Retention, EqualsSortingByVarianceThenIndexForAnyThreadCount) {
  const std::size_t n = 300007;  // several chunks, the last one partial
  const Field f = randomField(n, 7);
  const long long candidates = std::count(f.candidate.begin(), f.candidate.end(), 1);
  const long long tenth = static_cast<long long>(n / 10), half = static_cast<long long>(n / 2);
  for (long long keep :
       {0LL, 1LL, 1000LL, tenth, half, candidates - 1, candidates, candidates + 5}) {
    const std::vector<std::uint8_t> expected = keptByDefinition(f, keep);
    std::vector<std::uint8_t> serial(n, 7);
    const long long serial_count =
        mm::keepLowestVariance(f.variance.data(), f.candidate.data(), n, keep, serial.data());
    EXPECT_EQ(serial_count, std::count(expected.begin(), expected.end(), 1)) << "keep " << keep;
    EXPECT_EQ(serial, expected) << "serial, keep " << keep;
    for (int threads : {1, 2, 3, 8}) {
      mm::ThreadPool pool(threads);
      std::vector<std::uint8_t> parallel(n, 7);
      EXPECT_EQ(mm::keepLowestVariance(f.variance.data(), f.candidate.data(), n, keep,
                                       parallel.data(), &pool),
                serial_count);
      EXPECT_EQ(parallel, expected) << threads << " threads, keep " << keep;
    }
  }
}

TEST(Retention, CountIsRoundedShareOfAllPixels) {
  EXPECT_EQ(mm::retentionCount(80.0, 1000), 800);
  EXPECT_EQ(mm::retentionCount(33.3, 10), 3);
  EXPECT_EQ(mm::retentionCount(100.0, 2354176), 2354176);
  EXPECT_EQ(mm::retentionCount(0.0, 5), 0);
}

// Long runs of one variance (whole blocks of equal keys, runs crossing block and chunk boundaries,
// broken by single other values and by non-candidates), next to values that share the high bits
// of the run's value but not its key, as around the prior variance of local_gp.
TEST(Retention, RunsOfEqualVariance) {
  const std::size_t n = 3 * 65536 + 1000;  // several chunks, the last one partial
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> run_length(1, 700);
  std::uniform_int_distribution<int> pick(0, 9);
  std::uniform_int_distribution<std::uint32_t> low_bits(0, 3);
  const std::uint32_t prior = 0x441c4000u;  // 625.0f
  Field f;
  f.variance.resize(n);
  f.candidate.resize(n);
  for (std::size_t i = 0; i < n;) {
    const int p = pick(rng);
    // The run's value: the prior, a neighbour of it in the last bits, or far below it.
    const float value =
        p < 6 ? floatOfBits(prior) : (p < 9 ? floatOfBits(prior + low_bits(rng) - 2) : 1.0f + p);
    const std::size_t end = std::min(n, i + static_cast<std::size_t>(run_length(rng)));
    for (; i < end; ++i) {
      f.variance[i] = value;
      f.candidate[i] = pick(rng) != 0 || p < 3;
    }
  }
  // Blocks of 64 entirely one key and all candidates, aligned and across a chunk boundary.
  std::fill(f.variance.begin() + 64 * 10, f.variance.begin() + 64 * 20, floatOfBits(prior));
  std::fill(f.candidate.begin() + 64 * 10, f.candidate.begin() + 64 * 20, 1);
  std::fill(f.variance.begin() + 65536 - 640, f.variance.begin() + 65536 + 640, floatOfBits(prior));
  std::fill(f.candidate.begin() + 65536 - 640, f.candidate.begin() + 65536 + 640, 1);
  expectKeptByBits(f, keepsAtKeys(f, 16), "runs");
}

TEST(Retention, AllEqualVariances) {
  for (std::size_t n : {std::size_t(1), std::size_t(63), std::size_t(64), std::size_t(65),
                        std::size_t(65536), std::size_t(65536 * 2 + 7)}) {
    Field f;
    f.variance.assign(n, 625.0f);
    f.candidate.assign(n, 1);
    const long long all = static_cast<long long>(n);
    expectKeptByBits(f, {all / 3, all / 2, 64, 65, 65536, 65537}, "all equal");
  }
}

// +inf, NaN, -0, negative values and subnormals rank by their bits: after the finite values >= 0
// (negative ones last), -0 after +0.
TEST(Retention, SpecialValuesRankByTheirBits) {
  const std::size_t n = 70001;
  std::mt19937 rng(3);
  const float specials[] = {std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(),
                            -0.0f,
                            0.0f,
                            -1.0f,
                            std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::max(),
                            4.0f};
  std::uniform_int_distribution<int> pick(0, 7);
  Field f;
  f.variance.resize(n);
  f.candidate.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    f.variance[i] = specials[pick(rng)];
    f.candidate[i] = pick(rng) != 0;
  }
  expectKeptByBits(f, keepsAtKeys(f, 8), "special values");
}

TEST(Retention, NoCandidatesAndNoPixels) {
  Field none;
  none.variance.assign(1000, 1.0f);
  none.candidate.assign(1000, 0);
  expectKeptByBits(none, {5}, "no candidates");
  expectKeptByBits(Field{}, {5}, "no pixels");
}

// The steps as DepthCompleter runs them: chunks counted in any order on any worker.
TEST(Retention, StepsInAnyChunkOrder) {
  const Field f = randomField(200003, 5);
  const std::size_t n = f.variance.size();
  const long long keep = static_cast<long long>(n / 3);
  mm::VarianceSelection selection(n, 3);
  for (long long c = selection.chunks() - 1; c >= 0; --c)
    selection.count(c, static_cast<int>(c % 3), f.variance.data(), f.candidate.data());
  mm::ThreadPool pool(2);
  EXPECT_EQ(selection.select(keep, f.variance.data(), f.candidate.data(), &pool), keep);
  std::vector<std::uint8_t> kept(n, 7);
  long long marked = 0;
  for (long long c = 0; c < selection.chunks(); ++c)
    marked += selection.mark(c, f.variance.data(), f.candidate.data(), kept.data());
  EXPECT_EQ(marked, keep);
  EXPECT_EQ(kept, keptByDefinition(f, keep));
}
