#pragma once
#include <cstddef>
#include <cstdint>

namespace multimodal_nvs {

class ThreadPool;

/// Number of pixels the reference keeps for "keep p%": round(p/100 * total_pixels).
long long retentionCount(double retain_percent, long long total_pixels);

/// Marks in `kept` the `keep_count` candidates (candidate[i] != 0) with the lowest variance; ties
/// are broken by the lower index (row-major pixel order), so the result is deterministic. Variances
/// of candidates must be finite and >= 0. Runs in linear time (radix select on the float bits).
/// Returns the number kept: min(keep_count, number of candidates). With a pool the passes run in
/// parallel; the result is the same for any thread count.
long long keepLowestVariance(const float* variance, const std::uint8_t* candidate, std::size_t n,
                             long long keep_count, std::uint8_t* kept, ThreadPool* pool = nullptr);

}  // namespace multimodal_nvs
