#include "multimodal_nvs/core/common/camera.hpp"

#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace {

// The radial factor and tangential terms of OpenCV's model (calib3d's projectPoints, without
// the thin-prism and tilt terms that ROS's models do not carry). Written out because it runs per
// projected point and cv::projectPoints would need a Mat per call.
void applyDistortion(const std::array<double, 8>& k, double x, double y, double* xd, double* yd) {
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double radial =
      (1.0 + k[0] * r2 + k[1] * r4 + k[4] * r6) / (1.0 + k[5] * r2 + k[6] * r4 + k[7] * r6);
  *xd = x * radial + 2.0 * k[2] * x * y + k[3] * (r2 + 2.0 * x * x);
  *yd = y * radial + k[2] * (r2 + 2.0 * y * y) + 2.0 * k[3] * x * y;
}

// The radius (normalised) up to which the distorted radius grows with the undistorted one in every
// direction; beyond it the model folds back (far rays would land back inside the image). Along the
// direction (cos a, sin a), applyDistortion's component along the ray is
//   r R(r^2) + 3 r^2 (p1 sin a + p2 cos a),   R = the radial factor, (p1, p2) = (k[2], k[3]),
// because the tangential terms sum to r^2 (p1 s (2 c^2 + 1 + 2 s^2) + p2 c (1 + 2 c^2 + 2 s^2)).
// Only the last term depends on the direction, linearly, so the direction that folds first is the
// one where p1 sin a + p2 cos a takes its minimum, -hypot(p1, p2): one scan along it bounds every
// direction (a scan of 16 sampled directions cost 1 ms per camera and missed the ones between).
// Checked up to r = 10 (84 degrees off axis) in 1/1000 steps.
double monotoneRadius(const std::array<double, 8>& k) {
  constexpr double kStep = 1e-3, kMax = 10.0;
  const double tangential = -3.0 * std::hypot(k[2], k[3]);
  double previous = 0.0;
  for (double r = kStep; r <= kMax; r += kStep) {
    const double r2 = r * r, r4 = r2 * r2, r6 = r4 * r2;
    const double radial =
        (1.0 + k[0] * r2 + k[1] * r4 + k[4] * r6) / (1.0 + k[5] * r2 + k[6] * r4 + k[7] * r6);
    const double along = r * radial + r2 * tangential;
    if (!(along > previous)) return r - kStep;
    previous = along;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

LensDistortion LensDistortion::fromRos(const std::string& model, const std::vector<double>& d,
                                       const std::string& source) {
  LensDistortion out;
  std::size_t expected = 0;
  if (model == "plumb_bob") {
    expected = 5;
  } else if (model == "rational_polynomial") {
    expected = 8;
  } else if (model.empty() || model == "none") {
    expected = 0;
  } else {
    throw InputError(source + ": distortion model '" + model +
                     "' is not supported (supported: plumb_bob, rational_polynomial, none)");
  }
  const bool all_zero = [&] {
    for (double v : d)
      if (v != 0.0) return false;
    return true;
  }();
  // An empty or all-zero D is a pinhole camera whatever the model's name (drivers publish
  // plumb_bob with five zeros or an empty D for a rectified image).
  if (all_zero) return out;
  if (d.size() != expected) {
    throw InputError(source + ": distortion model '" + (model.empty() ? "(none)" : model) +
                     "' needs " + std::to_string(expected) + " coefficients in D, got " +
                     std::to_string(d.size()));
  }
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (!std::isfinite(d[i])) {
      throw InputError(source + ": distortion model '" + model + "' has a non-finite D[" +
                       std::to_string(i) + "]");
    }
    out.coefficients[i] = d[i];
  }
  out.model = expected == 5 ? Model::kPlumbBob : Model::kRationalPolynomial;
  out.monotone_radius = monotoneRadius(out.coefficients);
  if (!(out.monotone_radius > 0.05)) {
    throw InputError(source + ": distortion model '" + model +
                     "' with these coefficients folds back within 3 degrees of the axis");
  }
  return out;
}

int LensDistortion::coefficientCount() const {
  switch (model) {
    case Model::kPlumbBob:
      return 5;
    case Model::kRationalPolynomial:
      return 8;
    case Model::kNone:
      break;
  }
  return 0;
}

std::string LensDistortion::rosName() const {
  switch (model) {
    case Model::kPlumbBob:
      return "plumb_bob";
    case Model::kRationalPolynomial:
      return "rational_polynomial";
    case Model::kNone:
      break;
  }
  return "";
}

bool LensDistortion::distort(double x, double y, double* xd, double* yd) const {
  if (!any()) {
    *xd = x;
    *yd = y;
    return true;
  }
  if (!(x * x + y * y <= monotone_radius * monotone_radius)) return false;
  applyDistortion(coefficients, x, y, xd, yd);
  // A lens whose radial terms never fold has no finite radius, but the polynomial still overflows
  // far out (r^4 = inf, and 0 * inf = NaN for an unused term): such a direction is outside what
  // the model describes, not a pixel.
  return std::isfinite(*xd) && std::isfinite(*yd);
}

Eigen::Matrix3d PinholeIntrinsics::matrix() const {
  Eigen::Matrix3d k;
  k << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return k;
}

PinholeIntrinsics PinholeIntrinsics::scaledTo(int from_height, int from_width, int to_height,
                                              int to_width) const {
  const double sx = static_cast<double>(to_width) / from_width;
  const double sy = static_cast<double>(to_height) / from_height;
  return {fx * sx, fy * sy, cx * sx, cy * sy, distortion};
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

bool PinholeIntrinsics::projectDistorted(double x, double y, double z, double* u, double* v) const {
  double xd = 0, yd = 0;
  if (!distortion.distort(x / z, y / z, &xd, &yd)) return false;
  *u = fx * xd + cx;
  *v = fy * yd + cy;
  return true;
}

void PinholeIntrinsics::normalisedRays(std::vector<Eigen::Vector2d>& pixels) const {
  if (pixels.empty()) return;
  if (!distortion.any()) {
    for (Eigen::Vector2d& p : pixels)
      p = Eigen::Vector2d((p.x() - cx) / fx, (p.y() - cy) / fy);
    return;
  }
  std::vector<cv::Point2d> in(pixels.size()), out;
  for (std::size_t i = 0; i < pixels.size(); ++i)
    in[i] = {pixels[i].x(), pixels[i].y()};
  const cv::Matx33d k(fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0);
  const cv::Mat d(1, distortion.coefficientCount(), CV_64F,
                  const_cast<double*>(distortion.coefficients.data()));
  // OpenCV's default is 5 fixed-point iterations, short of convergence for strong distortion at
  // the image corners; iterate until the step is below 1e-12 (normalised units).
  cv::undistortPoints(
      in, out, k, d, cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-12));
  for (std::size_t i = 0; i < pixels.size(); ++i)
    pixels[i] = Eigen::Vector2d(out[i].x, out[i].y);
}

}  // namespace multimodal_nvs
