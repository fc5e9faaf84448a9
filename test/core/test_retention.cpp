// keepLowestVariance against a direct definition: sort candidates by (variance, index) and keep the
// first keep_count. Sizes span several chunks so that the parallel passes and the per-chunk tie
// quotas are exercised, with heavy ties (as when most pixels have the prior variance).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "multimodal_nvs/core/retention.hpp"
#include "multimodal_nvs/core/thread_pool.hpp"

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
