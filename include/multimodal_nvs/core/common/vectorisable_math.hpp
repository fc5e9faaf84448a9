#pragma once
// Scalar helpers spelled so that GCC vectorises the loops that use them: std::isfinite and the
// reference-returning std::min / std::max kept full-image passes scalar (GCC 12, measured in the
// retention pass, ground_gp's prior and image_guided's per-pixel passes). Same results as the std
// versions for every input, NaN included.
#include <cmath>
#include <limits>

namespace multimodal_nvs {

/// std::isfinite(x): NaN fails the comparison, infinity exceeds the largest float.
inline bool isFiniteVectorisable(float x) {
  return std::fabs(x) <= std::numeric_limits<float>::max();
}

/// std::min(a, b) by value (b only when it is strictly less).
inline float minOf(float a, float b) {
  return b < a ? b : a;
}

/// std::max(a, b) by value (b only when a is strictly less).
inline float maxOf(float a, float b) {
  return a < b ? b : a;
}

}  // namespace multimodal_nvs
