#pragma once
// Pinhole intrinsics, image size and the rigid sensor-to-camera transform.
#include <Eigen/Core>
#include <string>

namespace multimodal_nvs {

/// Pinhole intrinsics in pixels (OpenCV optical frame: x right, y down, z forward).
struct PinholeIntrinsics {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;

  Eigen::Matrix3d matrix() const;
  /// Scales per axis to a new image size, as GEN3C does (aspect ratio stretched, no half-pixel
  /// shift).
  PinholeIntrinsics scaledTo(int from_height, int from_width, int to_height, int to_width) const;
  /// Throws InputError naming `source` unless all values are finite and fx, fy > 0.
  void validate(const std::string& source) const;
};

struct ImageSize {
  int height = 0;
  int width = 0;
  long long pixels() const { return static_cast<long long>(height) * width; }
  bool operator==(const ImageSize& o) const { return height == o.height && width == o.width; }
};

/// Rigid transform sensor -> camera as the 3x4 row-major matrix of KITTI's `Tr_velo_to_cam`.
using SensorToCamera = Eigen::Matrix<double, 3, 4>;

}  // namespace multimodal_nvs
