#include "multimodal_nvs/core/retention.hpp"

#include <cmath>
#include <cstring>
#include <vector>

namespace multimodal_nvs {
namespace {
// For non-negative floats the IEEE bit pattern orders like the value.
inline std::uint32_t bitsOf(float v) {
  std::uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
}  // namespace

long long retentionCount(double retain_percent, long long total_pixels) {
  return std::llround(retain_percent / 100.0 * static_cast<double>(total_pixels));
}

long long keepLowestVariance(const float* variance, const std::uint8_t* candidate, std::size_t n,
                             long long keep_count, std::uint8_t* kept) {
  std::memset(kept, 0, n);
  long long candidates = 0;
  for (std::size_t i = 0; i < n; ++i) candidates += candidate[i] != 0;
  if (keep_count <= 0 || candidates == 0) return 0;
  if (keep_count >= candidates) {
    for (std::size_t i = 0; i < n; ++i) kept[i] = candidate[i] != 0;
    return candidates;
  }
  // Two 16-bit radix passes find the exact variance value T of the keep_count-th smallest.
  std::vector<long long> histogram(1 << 16, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (candidate[i]) ++histogram[bitsOf(variance[i]) >> 16];
  }
  long long below = 0;
  std::uint32_t high = 0;
  for (; high < (1u << 16); ++high) {
    if (below + histogram[high] >= keep_count) break;
    below += histogram[high];
  }
  std::fill(histogram.begin(), histogram.end(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = bitsOf(variance[i]);
    if (candidate[i] && (b >> 16) == high) ++histogram[b & 0xffffu];
  }
  std::uint32_t low = 0;
  for (; low < (1u << 16); ++low) {
    if (below + histogram[low] >= keep_count) break;
    below += histogram[low];
  }
  const std::uint32_t threshold = (high << 16) | low;
  // Everything strictly below T is kept; pixels equal to T fill the remaining quota in index order.
  long long quota_at_threshold = keep_count - below;
  for (std::size_t i = 0; i < n; ++i) {
    if (!candidate[i]) continue;
    const std::uint32_t b = bitsOf(variance[i]);
    if (b < threshold) {
      kept[i] = 1;
    } else if (b == threshold && quota_at_threshold > 0) {
      kept[i] = 1;
      --quota_at_threshold;
    }
  }
  return keep_count;
}

}  // namespace multimodal_nvs
