#pragma once
// Visiting the set bytes of a sparse byte mask (the sky in a row of pixels) eight at a time: a
// loop that tests every byte cannot be vectorised next to float stores (GCC 12) and cost a third
// of image_guided's last per-pixel pass, where most bytes are 0.
#include <cstdint>
#include <cstring>

namespace multimodal_nvs {

/// Calls visit(i) for every i < count with mask[i] != 0, in increasing order.
template <class Visit>
inline void forEachSetByte(const std::uint8_t* mask, int count, Visit&& visit) {
  int i = 0;
  while (i < count) {
    if (i + 8 <= count) {
      std::uint64_t word;
      std::memcpy(&word, mask + i, sizeof(word));
      if (word == 0) {
        i += 8;
        continue;
      }
    }
    const int end = i + 8 < count ? i + 8 : count;
    for (; i < end; ++i) {
      if (mask[i]) visit(i);
    }
  }
}

}  // namespace multimodal_nvs
