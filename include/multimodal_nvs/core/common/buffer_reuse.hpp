#pragma once
// When a buffer reused across frames should be freed instead of kept.
#include <cstddef>

namespace multimodal_nvs {

/// True when a buffer of `capacity` elements is far larger than the `needed` ones (over four times
/// plus 64k): left behind by one huge input, it would pin that memory for the rest of the run.
constexpr bool capacityFarExceeds(std::size_t capacity, std::size_t needed) {
  return capacity > 4 * needed + (std::size_t(1) << 16);
}

}  // namespace multimodal_nvs
