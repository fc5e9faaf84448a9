#pragma once
// Pinhole intrinsics with optional lens distortion, image size and the rigid sensor-to-camera
// transform.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace multimodal_nvs {

/// Lens distortion as ROS's sensor_msgs/CameraInfo states it (`distortion_model`, `D`). Both
/// supported models are OpenCV's, in its coefficient order: `plumb_bob` (k1, k2, p1, p2, k3) and
/// `rational_polynomial` (k1, k2, p1, p2, k3, k4, k5, k6). Distortion applies to normalised image
/// coordinates (x = X/Z, y = Y/Z), so it is independent of the image scale.
struct LensDistortion {
  enum class Model { kNone, kPlumbBob, kRationalPolynomial };
  Model model = Model::kNone;
  std::array<double, 8> coefficients{};  ///< unused trailing coefficients stay 0
  /// Past this normalised radius the model stops being monotone (it would fold far rays back into
  /// the image); projection refuses such rays. Infinite when no fold exists within the checked
  /// range.
  double monotone_radius = 0.0;

  /// From CameraInfo's `distortion_model` and `D`. All-zero coefficients give kNone, so an
  /// undistorted camera takes the pinhole code paths unchanged. Throws InputError naming `source`
  /// and the model when it is unsupported (e.g. `equidistant`), D has the wrong length or a
  /// non-finite value.
  static LensDistortion fromRos(const std::string& model, const std::vector<double>& d,
                                const std::string& source);
  bool any() const { return model != Model::kNone; }
  /// Number of coefficients the model uses (0, 5 or 8).
  int coefficientCount() const;
  /// ROS's name of the model ("" for none).
  std::string rosName() const;
  /// Undistorted normalised (x, y) -> distorted normalised; false beyond `monotone_radius` or
  /// where the polynomial overflows.
  bool distort(double x, double y, double* xd, double* yd) const;
  bool operator==(const LensDistortion& o) const {
    return model == o.model && coefficients == o.coefficients;
  }
};

/// Pinhole intrinsics in pixels (OpenCV optical frame: x right, y down, z forward), plus the lens
/// distortion between the pinhole projection and the pixel (none by default).
struct PinholeIntrinsics {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  LensDistortion distortion;

  PinholeIntrinsics() = default;
  PinholeIntrinsics(double fx_, double fy_, double cx_, double cy_, LensDistortion distortion_ = {})
      : fx(fx_), fy(fy_), cx(cx_), cy(cy_), distortion(distortion_) {}

  Eigen::Matrix3d matrix() const;
  /// Scales per axis to a new image size, as GEN3C does (aspect ratio stretched, no half-pixel
  /// shift). The distortion (in normalised coordinates) is kept.
  PinholeIntrinsics scaledTo(int from_height, int from_width, int to_height, int to_width) const;
  /// Throws InputError naming `source` unless all values are finite and fx, fy > 0.
  void validate(const std::string& source) const;
  /// The same camera without its distortion (for cameras the renderer synthesises).
  PinholeIntrinsics pinhole() const { return {fx, fy, cx, cy}; }
  /// Camera point (Z > 0) -> pixel, through the distortion. False when the ray is past the
  /// distortion's monotone range.
  bool project(double x, double y, double z, double* u, double* v) const {
    if (distortion.any()) return projectDistorted(x, y, z, u, v);
    *u = fx * x / z + cx;
    *v = fy * y / z + cy;
    return true;
  }
  /// Pixels -> undistorted normalised rays (x = X/Z, y = Y/Z, y down), in place as (u, v) pairs.
  /// Iterative for a distorted camera (OpenCV's undistortPoints run to convergence), exact
  /// division otherwise.
  void normalisedRays(std::vector<Eigen::Vector2d>& pixels) const;

 private:
  bool projectDistorted(double x, double y, double z, double* u, double* v) const;
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
