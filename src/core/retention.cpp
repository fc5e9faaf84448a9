#include "multimodal_nvs/core/retention.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "multimodal_nvs/core/thread_pool.hpp"

namespace multimodal_nvs {
namespace {

constexpr std::size_t kChunk = 1 << 16;
constexpr std::size_t kBuckets = 1 << 16;

// For non-negative floats the IEEE bit pattern orders like the value.
inline std::uint32_t bitsOf(float v) {
  std::uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// Runs body(chunk, worker) over the chunks of [0, n): on the pool, or inline without one.
template <typename Body>
void forChunks(ThreadPool* pool, std::size_t n, const Body& body) {
  const long long chunks = static_cast<long long>((n + kChunk - 1) / kChunk);
  if (pool == nullptr) {
    for (long long c = 0; c < chunks; ++c)
      body(c, 0);
  } else {
    pool->parallelFor(chunks, body);
  }
}

struct ChunkRange {
  std::size_t begin, end;
};
ChunkRange chunkRange(long long chunk, std::size_t n) {
  const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
  return {begin, std::min(n, begin + kChunk)};
}

// Index of the bucket holding the keep_count-th smallest value, and how many lie below it.
std::uint32_t selectBucket(const std::vector<std::vector<std::uint32_t>>& histograms,
                           long long keep_count, long long& below) {
  for (std::uint32_t bucket = 0; bucket < kBuckets; ++bucket) {
    long long in_bucket = 0;
    for (const auto& h : histograms)
      in_bucket += h[bucket];
    if (below + in_bucket >= keep_count) return bucket;
    below += in_bucket;
  }
  return kBuckets - 1;  // unreachable while keep_count <= candidates
}

}  // namespace

long long retentionCount(double retain_percent, long long total_pixels) {
  return std::llround(retain_percent / 100.0 * static_cast<double>(total_pixels));
}

long long keepLowestVariance(const float* variance, const std::uint8_t* candidate, std::size_t n,
                             long long keep_count, std::uint8_t* kept, ThreadPool* pool) {
  // Every pass runs per chunk: per-worker histograms and per-chunk counts are summed afterwards,
  // so the result does not depend on the thread count. Counts fit 32 bits per worker (n < 2^32).
  const int workers = pool == nullptr ? 1 : pool->size();
  std::vector<std::vector<std::uint32_t>> histograms(workers);
  const long long chunks = static_cast<long long>((n + kChunk - 1) / kChunk);
  std::vector<long long> per_chunk(chunks, 0);

  // Pass 1: candidates, and a histogram of the high 16 bits of their variance.
  forChunks(pool, n, [&](long long c, int worker) {
    auto& h = histograms[worker];
    if (h.empty()) h.assign(kBuckets, 0);
    const ChunkRange r = chunkRange(c, n);
    long long count = 0;
    for (std::size_t i = r.begin; i < r.end; ++i) {
      if (!candidate[i]) continue;
      ++count;
      ++h[bitsOf(variance[i]) >> 16];
    }
    per_chunk[c] = count;
  });
  long long candidates = 0;
  for (long long count : per_chunk)
    candidates += count;
  for (auto& h : histograms)
    h.resize(kBuckets, 0);  // workers that got no chunk

  if (keep_count <= 0 || keep_count >= candidates) {
    const bool keep_all = keep_count > 0;
    forChunks(pool, n, [&](long long c, int) {
      const ChunkRange r = chunkRange(c, n);
      for (std::size_t i = r.begin; i < r.end; ++i)
        kept[i] = keep_all & (candidate[i] != 0);
    });
    return keep_all ? candidates : 0;
  }

  // Pass 2: the low 16 bits within the selected high bucket give the exact threshold value T.
  long long below = 0;
  const std::uint32_t high = selectBucket(histograms, keep_count, below);
  for (auto& h : histograms)
    std::fill(h.begin(), h.end(), 0);
  forChunks(pool, n, [&](long long c, int worker) {
    auto& h = histograms[worker];
    const ChunkRange r = chunkRange(c, n);
    for (std::size_t i = r.begin; i < r.end; ++i) {
      const std::uint32_t b = bitsOf(variance[i]);
      if (candidate[i] && (b >> 16) == high) ++h[b & 0xffffu];
    }
  });
  const std::uint32_t threshold = (high << 16) | selectBucket(histograms, keep_count, below);

  // Pass 3: everything strictly below T is kept; ties at T are counted per chunk.
  forChunks(pool, n, [&](long long c, int) {
    const ChunkRange r = chunkRange(c, n);
    long long ties = 0;
    for (std::size_t i = r.begin; i < r.end; ++i) {
      const std::uint32_t b = bitsOf(variance[i]);
      const bool is_candidate = candidate[i] != 0;
      kept[i] = is_candidate & (b < threshold);
      ties += is_candidate & (b == threshold);
    }
    per_chunk[c] = ties;
  });
  // Ties fill the remaining quota in index order: each chunk learns how many of its ties to keep.
  std::vector<long long> tie_quota(chunks, 0);
  long long quota = keep_count - below;
  for (long long c = 0; c < chunks; ++c) {
    tie_quota[c] = std::min(quota, per_chunk[c]);
    quota -= tie_quota[c];
  }
  forChunks(pool, n, [&](long long c, int) {
    long long remaining = tie_quota[c];
    if (remaining == 0) return;
    const ChunkRange r = chunkRange(c, n);
    for (std::size_t i = r.begin; i < r.end && remaining > 0; ++i) {
      if (candidate[i] && bitsOf(variance[i]) == threshold) {
        kept[i] = 1;
        --remaining;
      }
    }
  });
  return keep_count;
}

}  // namespace multimodal_nvs
