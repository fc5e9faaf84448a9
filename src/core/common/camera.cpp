#include "multimodal_nvs/core/common/camera.hpp"

#include <cmath>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

Eigen::Matrix3d PinholeIntrinsics::matrix() const {
  Eigen::Matrix3d k;
  k << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return k;
}

PinholeIntrinsics PinholeIntrinsics::scaledTo(int from_height, int from_width, int to_height,
                                              int to_width) const {
  const double sx = static_cast<double>(to_width) / from_width;
  const double sy = static_cast<double>(to_height) / from_height;
  return {fx * sx, fy * sy, cx * sx, cy * sy};
}

void PinholeIntrinsics::validate(const std::string& source) const {
  if (!std::isfinite(fx) || !std::isfinite(fy) || !std::isfinite(cx) || !std::isfinite(cy)) {
    throw InputError(source + ": intrinsics contain a non-finite value");
  }
  if (fx <= 0.0 || fy <= 0.0) {
    throw InputError(source + ": focal length must be positive (fx=" + std::to_string(fx) +
                     ", fy=" + std::to_string(fy) + ")");
  }
}

}  // namespace multimodal_nvs
