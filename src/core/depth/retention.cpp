#include "multimodal_nvs/core/depth/retention.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "multimodal_nvs/core/common/per_worker.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {
namespace {

// Radix select on the variance bits read as unsigned integers, in three digits: the high 14 bits
// (sign, exponent, 5 mantissa bits), then two digits of 9 bits. The first digit is histogrammed in
// the caller's first pass over the pixels. One more pass gathers the candidates of the boundary
// bucket as runs of consecutive pixels with one key: few pixels have a variance that close to the
// threshold, and where many tie at one variance (local_gp's prior: two thirds of the image in the
// VoD radar benchmark) they come in long runs, so there are some 15 000 to 20 000 runs either way.
// The further digits, the threshold's ties and the cut between kept and dropped ties are then found
// on these runs only, and one last pass marks the kept pixels by comparing with the threshold.
constexpr int kShift1 = 18;
constexpr std::size_t kBuckets1 = std::size_t(1) << (32 - kShift1);
constexpr int kDigitBits = kShift1 / 2;  // second and third digit
constexpr std::size_t kBuckets = std::size_t(1) << kDigitBits;
static_assert(kShift1 == 2 * kDigitBits, "the three digits cover the 32 bits");
// Sub-histograms per worker, pixel i counting into sub-histogram i % kSub: neighbouring pixels
// often share a bucket, and consecutive increments of one counter would wait on each other's store
// (several cycles each).
constexpr std::size_t kSub = 4;
// Sub-histograms lie a cache line more than a multiple of 4 KiB apart: at a multiple (same low
// address bits), counting was 5-15 % slower, as if loads waited on the other sub-histograms'
// stores.
constexpr std::size_t kPad = 16;
constexpr std::size_t kStride1 = kBuckets1 + kPad;
constexpr std::size_t kStride = kBuckets + kPad;
constexpr std::size_t kChunk = VarianceSelection::kChunk;
// Pixels are tested in blocks; a block of one key (runs of the prior variance) is handled at once.
constexpr std::size_t kBlock = 64;

// For non-negative floats the IEEE bit pattern orders like the value.
inline std::uint32_t bitsOf(float v) {
  std::uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

struct ChunkRange {
  std::size_t begin, end;
};
ChunkRange chunkRange(long long chunk, std::size_t n) {
  const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
  return {begin, std::min(n, begin + kChunk)};
}

// The block functions below work on kBlock pixels (a constant trip count: fully vectorised) and
// take restrict pointers so that GCC keeps values in registers (stores through uint8_t* may
// otherwise alias everything); the reductions have no early exit for the same reason.

// Calls visit(offset, variance, candidate) for the blocks of [0, count) in order, with pointers
// that may also be read at [-1]: the pixel before the block. The first block gets a non-candidate
// there, and a last, partial block is padded with non-candidates (whose keys matter to no count);
// both are copied for that.
template <typename Visit>
void forBlocks(const float* variance, const std::uint8_t* candidate, std::size_t count,
               const Visit& visit) {
  for (std::size_t block = 0; block < count; block += kBlock) {
    if (block > 0 && block + kBlock <= count) {
      visit(block, variance + block, candidate + block);
      continue;
    }
    float v[kBlock + 1] = {};
    std::uint8_t c[kBlock + 1] = {};
    if (block > 0) {
      v[0] = variance[block - 1];
      c[0] = candidate[block - 1];
    }
    const std::size_t size = std::min(kBlock, count - block);
    std::copy(variance + block, variance + block + size, v + 1);
    std::copy(candidate + block, candidate + block + size, c + 1);
    visit(block, v + 1, c + 1);
  }
}

bool allCandidates(const std::uint8_t* __restrict candidate) {
  std::uint8_t all = 1;
  for (std::size_t i = 0; i < kBlock; ++i)
    all &= candidate[i] != 0;
  return all;
}

// Whether the first digit is the same for every pixel of the block.
bool oneBucket(const float* __restrict variance) {
  const std::uint32_t first = bitsOf(variance[0]) >> kShift1;
  std::uint32_t differ = 0;
  for (std::size_t i = 0; i < kBlock; ++i)
    differ |= (bitsOf(variance[i]) >> kShift1) ^ first;
  return differ == 0;
}

// Whether any key of the block lies in the bucket (candidate or not: a cheaper test on keys alone),
// and whether all its keys are equal.
struct BlockKeys {
  bool any_in_bucket, uniform;
};
BlockKeys blockKeys(const float* __restrict variance, std::uint32_t bucket) {
  const std::uint32_t first = bitsOf(variance[0]);
  std::uint32_t any = 0, differ = 0;
  for (std::size_t i = 0; i < kBlock; ++i) {
    any |= (bitsOf(variance[i]) >> kShift1) == bucket;
    differ |= bitsOf(variance[i]) ^ first;
  }
  return {any != 0, differ == 0};
}

// First digit: h[s * kStride1 + b] counts the candidates of the block with key >> kShift1 == b
// among its pixels s, s + kSub, ... Returns the block's candidate count.
std::uint32_t histogramFirst(const float* __restrict variance,
                             const std::uint8_t* __restrict candidate,
                             std::uint32_t* __restrict h) {
  if (!allCandidates(candidate)) {  // non-candidates add 0
    std::uint32_t candidates = 0;
    for (std::size_t i = 0; i < kBlock; ++i) {
      const std::uint32_t is_candidate = candidate[i] != 0;
      h[(i % kSub) * kStride1 + (bitsOf(variance[i]) >> kShift1)] += is_candidate;
      candidates += is_candidate;
    }
    return candidates;
  }
  if (oneBucket(variance)) {
    h[bitsOf(variance[0]) >> kShift1] += kBlock;
  } else {
    for (std::size_t i = 0; i < kBlock; i += kSub) {
      for (std::size_t s = 0; s < kSub; ++s)  // unrolled: constant sub-histogram offsets
        ++h[s * kStride1 + (bitsOf(variance[i + s]) >> kShift1)];
    }
  }
  return kBlock;
}

// Of the pixels i of a block: in[i] = candidate with key >> kShift1 == bucket; boundary[i] = 1
// where a run of such pixels with one key ends or begins between pixel i - 1 and i (pixel -1: see
// forBlocks).
void runBoundaries(const float* __restrict variance, const std::uint8_t* __restrict candidate,
                   std::uint32_t bucket, std::uint8_t* __restrict in,
                   std::uint8_t* __restrict boundary) {
  for (std::size_t i = 0; i < kBlock; ++i) {
    const std::uint32_t key = bitsOf(variance[i]), before = bitsOf(variance[i - 1]);
    const bool is_in = (candidate[i] != 0) & ((key >> kShift1) == bucket);
    const bool was_in = (candidate[i - 1] != 0) & ((before >> kShift1) == bucket);
    in[i] = is_in;
    boundary[i] = (is_in != was_in) | (is_in & (key != before));
  }
}

struct Run {
  std::uint32_t begin, end, key;  // pixels [begin, end) of a chunk, all candidates with one key
};

// The candidates with key >> kShift1 == `bucket` in one chunk, as runs of consecutive pixels with
// one key, in index order. Blocks without any are skipped after a vectorised test, blocks of one
// key extend or start a run at once, and in the other blocks only the run boundaries are visited.
void gatherRuns(const float* variance, const std::uint8_t* candidate, std::size_t count,
                std::uint32_t bucket, std::vector<Run>& runs) {
  // Whether a run takes in the pixel before the block, and that run. The chunk's first pixel
  // follows a non-candidate (see forBlocks): runs do not cross chunks.
  bool open = false;
  Run run{};
  alignas(64) std::uint8_t in[kBlock];
  alignas(64) std::uint8_t boundary[kBlock];
  forBlocks(variance, candidate, count,
            [&](std::size_t block, const float* v, const std::uint8_t* c) {
              const auto at = [&](std::size_t i) { return static_cast<std::uint32_t>(block + i); };
              const BlockKeys keys = blockKeys(v, bucket);
              if (!keys.any_in_bucket) {
                if (open) runs.push_back({run.begin, at(0), run.key});
                open = false;
                return;
              }
              if (keys.uniform && allCandidates(c)) {
                if (open && run.key == bitsOf(v[0])) return;  // the run goes on
                if (open) runs.push_back({run.begin, at(0), run.key});
                open = true;
                run = {at(0), 0, bitsOf(v[0])};
                return;
              }
              runBoundaries(v, c, bucket, in, boundary);
              for (std::size_t word = 0; word < kBlock; word += 8) {
                std::uint64_t bits;  // 0/1 bytes: byte j is bit 8 j
                std::memcpy(&bits, boundary + word, sizeof bits);
                for (; bits != 0; bits &= bits - 1) {
                  const std::size_t i = word + static_cast<std::size_t>(__builtin_ctzll(bits)) / 8;
                  if (open) runs.push_back({run.begin, at(i), run.key});
                  open = in[i];
                  run = {at(i), 0, bitsOf(v[i])};
                }
              }
            });
  // The padding of a partial block is no candidate: a run open here ends at the chunk's end.
  if (open) runs.push_back({run.begin, static_cast<std::uint32_t>(count), run.key});
}

// A further digit: h[s * kStride + d] counts the pixels of the runs whose key >> (shift +
// kDigitBits) == prefix by their digit d = (key >> shift) % kBuckets.
void histogramRuns(const Run* __restrict runs, std::size_t count, std::uint32_t prefix, int shift,
                   std::uint32_t* __restrict h) {
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t key = runs[k].key;
    const std::uint32_t digit = (key >> shift) & (kBuckets - 1);
    const bool counted = (key >> (shift + kDigitBits)) == prefix;
    h[(k % kSub) * kStride + digit] += counted ? runs[k].end - runs[k].begin : 0;
  }
}

// kept[i] = candidate and (key < threshold, or key == threshold if `ties`); returns the kept count.
// Branch-free so that it vectorises.
long long markRange(const float* __restrict variance, const std::uint8_t* __restrict candidate,
                    std::size_t count, std::uint32_t threshold, bool ties,
                    std::uint8_t* __restrict kept) {
  const std::uint8_t tie = ties;
  std::uint32_t total = 0;  // at most a chunk; narrower sums vectorise better
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t b = bitsOf(variance[i]);
    const std::uint8_t keep = (candidate[i] != 0) & ((b < threshold) | ((b == threshold) & tie));
    kept[i] = keep;
    total += keep;
  }
  return total;
}

// Index of the bucket holding the keep_count-th smallest value (counted from `below`, which is
// advanced past the lower buckets), summing the given histograms of `buckets` counters. Spans of
// buckets are summed first (vectorised) so that only the boundary's span is scanned bucket by
// bucket.
std::uint32_t selectBucket(const std::vector<const std::uint32_t*>& histograms, std::size_t buckets,
                           long long keep_count, long long& below) {
  constexpr std::size_t kSpan = 256;
  for (std::size_t first = 0; first < buckets; first += kSpan) {
    long long total = 0;
    for (const std::uint32_t* h : histograms) {
      for (std::size_t b = first; b < first + kSpan; ++b)
        total += h[b];
    }
    if (below + total < keep_count) {
      below += total;
      continue;
    }
    for (std::size_t b = first; b < first + kSpan; ++b) {
      long long in_bucket = 0;
      for (const std::uint32_t* h : histograms)
        in_bucket += h[b];
      if (below + in_bucket >= keep_count) return static_cast<std::uint32_t>(b);
      below += in_bucket;
    }
  }
  return static_cast<std::uint32_t>(buckets - 1);  // unreachable while keep_count <= candidates
}

}  // namespace

long long retentionCount(double retain_percent, long long total_pixels) {
  return std::llround(retain_percent / 100.0 * static_cast<double>(total_pixels));
}

// Every pass runs per chunk: per-worker histograms and per-chunk counts and runs are combined
// afterwards in chunk order, so the result does not depend on the thread count. Counts fit 32 bits
// per worker (n < 2^32). The scratch memory is allocated here, on the calling thread, and zeroed by
// each worker as it starts: allocated by the workers, it page-faulted afresh on most calls
// (measured ~130 more page faults per call, ~0.3 ms, as much as a pass over the pixels).
VarianceSelection::VarianceSelection(std::size_t n, int workers)
    : n_(n),
      chunks_(static_cast<long long>((n + kChunk - 1) / kChunk)),
      workers_(static_cast<std::size_t>(std::max(workers, 1))),
      histograms_(new std::uint32_t[workers_ * kSub * kStride1]),
      counting_(workers_, 0),
      candidates_in_chunk_(chunks_, 0) {}

VarianceSelection::~VarianceSelection() = default;

void VarianceSelection::count(long long chunk, int worker, const float* variance,
                              const std::uint8_t* candidate) {
  std::uint32_t* const h = histograms_.get() + worker * kSub * kStride1;
  if (!counting_[worker]) {
    std::fill(h, h + kSub * kStride1, 0);
    counting_[worker] = 1;
  }
  const ChunkRange r = chunkRange(chunk, n_);
  long long candidates = 0;
  forBlocks(variance + r.begin, candidate + r.begin, r.end - r.begin,
            [&](std::size_t, const float* v, const std::uint8_t* c) {
              candidates += histogramFirst(v, c, h);
            });
  candidates_in_chunk_[chunk] = candidates;
}

long long VarianceSelection::select(long long keep_count, const float* variance,
                                    const std::uint8_t* candidate, ThreadPool* pool) {
  long long candidates = 0;
  for (long long count : candidates_in_chunk_)
    candidates += count;
  if (keep_count <= 0) {  // no key is below 0, no tie before index 0
    threshold_ = 0;
    cut_ = 0;
    return 0;
  }
  if (keep_count >= candidates) {  // every key is <= the largest, every tie before n
    threshold_ = 0xffffffffu;
    cut_ = n_;
    return candidates;
  }
  if (pool != nullptr && static_cast<std::size_t>(pool->size()) > workers_) pool = nullptr;

  std::vector<const std::uint32_t*> parts;
  for (std::size_t w = 0; w < workers_; ++w) {
    for (std::size_t s = 0; counting_[w] && s < kSub; ++s)
      parts.push_back(histograms_.get() + (w * kSub + s) * kStride1);
  }
  long long below = 0;  // candidates with a key below the selected prefix
  const std::uint32_t first = selectBucket(parts, kBuckets1, keep_count, below);

  // Runs per worker; each chunk's runs are a range of its worker's.
  struct RunRange {
    std::size_t worker = 0, begin = 0, end = 0;
  };
  long long in_bucket = 0;
  for (const std::uint32_t* h : parts)
    in_bucket += h[first];
  PerWorker<std::vector<Run>> runs(static_cast<int>(workers_));
  // Reserved here rather than grown in the workers (see the constructor).
  for (int w = 0; w < runs.size(); ++w)
    runs[w].reserve(static_cast<std::size_t>(std::min<long long>(in_bucket, kChunk)));
  std::vector<RunRange> chunk_runs(chunks_);
  parallelForOrInline(pool, chunks_, [&](long long c, int worker) {
    const ChunkRange r = chunkRange(c, n_);
    std::vector<Run>& out = runs[worker];
    chunk_runs[c] = {static_cast<std::size_t>(worker), out.size(), 0};
    gatherRuns(variance + r.begin, candidate + r.begin, r.end - r.begin, first, out);
    chunk_runs[c].end = out.size();
  });
  const auto runsOf = [&](long long c) {
    return runs[static_cast<int>(chunk_runs[c].worker)].data();
  };

  // The next digit among the runs whose key starts with `prefix`.
  const auto nextDigit = [&](std::uint32_t prefix, int shift) {
    std::vector<char> used(workers_, 0);  // each worker writes its own entry
    parallelForOrInline(pool, chunks_, [&](long long c, int worker) {
      const RunRange& rr = chunk_runs[c];
      if (rr.begin == rr.end) return;
      std::uint32_t* const h = histograms_.get() + worker * kSub * kStride1;
      if (!used[worker]) {
        std::fill(h, h + kSub * kStride, 0);
        used[worker] = 1;
      }
      histogramRuns(runsOf(c) + rr.begin, rr.end - rr.begin, prefix, shift, h);
    });
    parts.clear();
    for (std::size_t w = 0; w < workers_; ++w) {
      for (std::size_t s = 0; used[w] && s < kSub; ++s)
        parts.push_back(histograms_.get() + w * kSub * kStride1 + s * kStride);
    }
    return (prefix << kDigitBits) | selectBucket(parts, kBuckets, keep_count, below);
  };
  threshold_ = nextDigit(nextDigit(first, kDigitBits), 0);

  // Ties at the threshold fill the remaining quota in index order: count them per chunk, then
  // find the index just past the last tie kept.
  std::vector<long long> ties(chunks_, 0);
  parallelForOrInline(pool, chunks_, [&](long long c, int) {
    long long t = 0;
    for (std::size_t k = chunk_runs[c].begin; k < chunk_runs[c].end; ++k) {
      const Run& run = runsOf(c)[k];
      if (run.key == threshold_) t += run.end - run.begin;
    }
    ties[c] = t;
  });
  long long quota = keep_count - below;  // >= 1: the threshold holds the keep_count-th candidate
  long long c = 0;
  while (quota > ties[c])
    quota -= ties[c++];
  for (std::size_t k = chunk_runs[c].begin;; ++k) {
    const Run& run = runsOf(c)[k];
    if (run.key != threshold_) continue;
    if (quota <= run.end - run.begin) {
      cut_ = chunkRange(c, n_).begin + run.begin + static_cast<std::size_t>(quota);
      break;
    }
    quota -= run.end - run.begin;
  }
  return keep_count;
}

long long VarianceSelection::mark(long long chunk, const float* variance,
                                  const std::uint8_t* candidate, std::uint8_t* kept) const {
  const ChunkRange r = chunkRange(chunk, n_);
  const std::size_t split = std::min(std::max(cut_, r.begin), r.end);  // ties kept before it
  return markRange(variance + r.begin, candidate + r.begin, split - r.begin, threshold_, true,
                   kept + r.begin) +
         markRange(variance + split, candidate + split, r.end - split, threshold_, false,
                   kept + split);
}

long long keepLowestVariance(const float* variance, const std::uint8_t* candidate, std::size_t n,
                             long long keep_count, std::uint8_t* kept, ThreadPool* pool) {
  VarianceSelection selection(n, pool == nullptr ? 1 : pool->size());
  parallelForOrInline(pool, selection.chunks(), [&](long long c, int worker) {
    selection.count(c, worker, variance, candidate);
  });
  const long long kept_count = selection.select(keep_count, variance, candidate, pool);
  parallelForOrInline(pool, selection.chunks(),
                      [&](long long c, int) { selection.mark(c, variance, candidate, kept); });
  return kept_count;
}

}  // namespace multimodal_nvs
