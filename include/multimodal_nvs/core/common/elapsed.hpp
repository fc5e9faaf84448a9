#pragma once
// Wall time since a steady_clock instant, in milliseconds (the timings in stats and reports).
#include <chrono>

namespace multimodal_nvs {

inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace multimodal_nvs
