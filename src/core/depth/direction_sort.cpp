#include "multimodal_nvs/core/depth/direction_sort.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace multimodal_nvs {
namespace {

/// A finite float's bits as an unsigned integer of the same order (-0 and +0 alike).
std::uint32_t orderedBits(float f) {
  if (f == 0.0f) f = 0.0f;
  std::uint32_t bits = 0;
  std::memcpy(&bits, &f, sizeof f);
  return (bits & 0x80000000u) != 0 ? ~bits : (bits | 0x80000000u);
}

}  // namespace

// A least-significant-digit radix sort of the directions as 64-bit keys (the two angles'
// order-preserving bits), 11 bits a pass, a pass skipped when every key has the same digit; then
// each run of one direction by depth. Hand-written because std::sort took 3-5 ms of the
// triangulation's thread on a VoD LiDAR frame (~25 k samples), the thread the pool then waits for.
void sortByDirectionThenDepth(std::vector<AngularSample>& samples) {
  const std::size_t n = samples.size();
  if (n < 2) return;
  std::vector<std::uint64_t> key(n), key_out(n);
  std::vector<int> index(n), index_out(n);
  for (std::size_t i = 0; i < n; ++i) {
    key[i] = (std::uint64_t(orderedBits(samples[i].elevation_deg)) << 32) |
             orderedBits(samples[i].azimuth_deg);
    index[i] = static_cast<int>(i);
  }
  constexpr int kDigitBits = 11, kBuckets = 1 << kDigitBits;
  constexpr int kPasses = (64 + kDigitBits - 1) / kDigitBits;
  std::vector<std::size_t> counts(std::size_t(kPasses) * kBuckets, 0);
  for (const std::uint64_t k : key) {
    for (int p = 0; p < kPasses; ++p)
      ++counts[std::size_t(p) * kBuckets + ((k >> (p * kDigitBits)) & (kBuckets - 1))];
  }
  for (int p = 0; p < kPasses; ++p) {
    const int shift = p * kDigitBits;
    std::size_t* const count = counts.data() + std::size_t(p) * kBuckets;
    if (count[(key[0] >> shift) & (kBuckets - 1)] == n) continue;
    std::size_t start = 0;
    for (int b = 0; b < kBuckets; ++b) {
      const std::size_t c = count[b];
      count[b] = start;
      start += c;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t at = count[(key[i] >> shift) & (kBuckets - 1)]++;
      key_out[at] = key[i];
      index_out[at] = index[i];
    }
    key.swap(key_out);
    index.swap(index_out);
  }
  // A repeated direction (rare): its run by depth.
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && key[j] == key[i])
      ++j;
    if (j - i > 1) {
      std::sort(index.begin() + static_cast<long>(i), index.begin() + static_cast<long>(j),
                [&](int a, int b) { return samples[a].depth < samples[b].depth; });
    }
    i = j;
  }
  std::vector<AngularSample> sorted(n);
  for (std::size_t i = 0; i < n; ++i)
    sorted[i] = samples[index[i]];
  samples.swap(sorted);
}

}  // namespace multimodal_nvs
