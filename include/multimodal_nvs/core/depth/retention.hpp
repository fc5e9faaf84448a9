#pragma once
// Retention ("keep p %" of the paper): the kept pixels are those with the lowest variance.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace multimodal_nvs {

class ThreadPool;

/// Number of pixels the reference keeps for "keep p%": round(p/100 * total_pixels).
long long retentionCount(double retain_percent, long long total_pixels);

/// Marks in `kept` the `keep_count` candidates (candidate[i] != 0) with the lowest variance; ties
/// are broken by the lower index (row-major pixel order), so the result is deterministic. Variances
/// are ranked by their IEEE bit pattern read as an unsigned integer, which orders finite values
/// >= 0 like the values themselves (candidates' variances should be such; +inf and NaN rank
/// above them, negative values last). Runs in linear time (radix select on the float bits).
/// Returns the number kept: min(keep_count, number of candidates). With a pool the passes run in
/// parallel; the result is the same for any thread count.
long long keepLowestVariance(const float* variance, const std::uint8_t* candidate, std::size_t n,
                             long long keep_count, std::uint8_t* kept, ThreadPool* pool = nullptr);

/// keepLowestVariance in steps, for callers that fuse its first and last pass over the pixels with
/// their own per-chunk work while the chunk is in cache (DepthCompleter marks the candidates
/// before count() and masks the depth after mark()). The pixels [0, n) are split into chunks of
/// kChunk; `variance` and `candidate` are the whole arrays and must not change between the steps.
///   VarianceSelection s(n, pool_size);
///   for every chunk (in any order, on any worker): s.count(chunk, worker, variance, candidate);
///   s.select(keep_count, variance, candidate, pool);
///   for every chunk: s.mark(chunk, variance, candidate, kept);
class VarianceSelection {
 public:
  static constexpr std::size_t kChunk = std::size_t(1) << 16;

  /// `workers`: the largest worker id passed to count(), plus one (a pool's size).
  VarianceSelection(std::size_t n, int workers);
  ~VarianceSelection();
  VarianceSelection(const VarianceSelection&) = delete;
  VarianceSelection& operator=(const VarianceSelection&) = delete;

  long long chunks() const { return chunks_; }

  /// First pass over one chunk: histograms its candidates' variances for worker `worker`. Calls
  /// for different chunks may run concurrently if their workers differ.
  void count(long long chunk, int worker, const float* variance, const std::uint8_t* candidate);

  /// After every chunk is counted: finds which candidates to keep, with one more pass over the
  /// pixels (gathering the few whose variance is close to the threshold) on `pool` (run serially
  /// if it has more threads than `workers`). Returns the number kept, min(keep_count, candidates).
  long long select(long long keep_count, const float* variance, const std::uint8_t* candidate,
                   ThreadPool* pool);

  /// Last pass over one chunk: writes kept (0/1) for its pixels and returns how many it keeps.
  /// Read-only on the selection: chunks may be marked concurrently.
  long long mark(long long chunk, const float* variance, const std::uint8_t* candidate,
                 std::uint8_t* kept) const;

 private:
  std::size_t n_;
  long long chunks_;
  std::size_t workers_;
  std::unique_ptr<std::uint32_t[]> histograms_;  // per worker, see count()
  std::vector<char> counting_;                   // per worker: its histogram is zeroed
  std::vector<long long> candidates_in_chunk_;
  // The kept set: candidates whose key (variance bits) is < threshold_, or == threshold_ at an
  // index < cut_ (the ties in index order).
  std::uint32_t threshold_ = 0;
  std::size_t cut_ = 0;
};

}  // namespace multimodal_nvs
