#include "multimodal_nvs/core/depth/return_density.hpp"

#include <algorithm>
#include <cmath>

namespace multimodal_nvs {
namespace {
constexpr double kRadToDeg = 180.0 / M_PI;

/// Degrees spanned by pixel edges -0.5 .. size - 0.5 around the principal point `c`.
double extentDeg(double focal, double c, int size) {
  return (std::atan((double(size) - 0.5 - c) / focal) + std::atan((c + 0.5) / focal)) * kRadToDeg;
}
}  // namespace

double viewSquareDegrees(const PinholeIntrinsics& k, const ImageSize& image) {
  if (image.width <= 0 || image.height <= 0 || !(k.fx > 0.0) || !(k.fy > 0.0)) return 0.0;
  return extentDeg(k.fx, k.cx, image.width) * extentDeg(k.fy, k.cy, image.height);
}

double returnDensity(std::size_t returns_in_view, const PinholeIntrinsics& k,
                     const ImageSize& image) {
  const double area = viewSquareDegrees(k, image);
  return area > 0.0 ? double(returns_in_view) / area : 0.0;
}

double priorWeightForDensity(double weight, double density, double reference_density) {
  if (!(reference_density > 0.0)) return weight;
  const double factor =
      std::clamp(density / reference_density, kMinPriorWeightFactor, kMaxPriorWeightFactor);
  return weight * factor;
}

}  // namespace multimodal_nvs
