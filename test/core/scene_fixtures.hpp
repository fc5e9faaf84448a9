#pragma once
// Small analytic scenes in the camera frame for the depth-completion tests.
#include <Eigen/Core>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"

namespace multimodal_nvs {
namespace test {

inline PinholeIntrinsics smallCamera() {
  return {100.0, 100.0, 80.0, 60.0};
}
inline ImageSize smallImage() {
  return {120, 160};
}

/// Camera-frame point on the ray of pixel (u, v) at camera depth z.
inline Eigen::Vector3d pointOnPixelRay(const PinholeIntrinsics& k, double u, double v, double z) {
  return {(u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z};
}

/// A grid of points on the fronto-parallel plane z = depth, one every `step` pixels.
inline std::vector<Eigen::Vector3d> planePoints(const PinholeIntrinsics& k, const ImageSize& image,
                                                double depth, int step) {
  std::vector<Eigen::Vector3d> points;
  for (int v = step / 2; v < image.height; v += step) {
    for (int u = step / 2; u < image.width; u += step)
      points.push_back(pointOnPixelRay(k, u, v, depth));
  }
  return points;
}

}  // namespace test
}  // namespace multimodal_nvs
