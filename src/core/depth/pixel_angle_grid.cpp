#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

#include <algorithm>
#include <cmath>

namespace multimodal_nvs {
namespace {
// numpy's degrees(): x * (180/pi) with the constant formed in the operand's precision.
constexpr float kRadToDeg32 = 180.0f / 3.14159265358979323846f;
}  // namespace

PixelAngleGrid::PixelAngleGrid(const PinholeIntrinsics& intrinsics, const StrideGrid& grid)
    : intrinsics_(intrinsics), grid_(grid) {
  const int rows = grid.rows();
  const int cols = grid.cols();
  azimuth_.resize(std::size_t(rows) * cols + kRowReadPadding);
  elevation_.resize(std::size_t(rows) * cols + kRowReadPadding);
  row_min_elevation_.resize(rows);
  row_max_elevation_.resize(rows);
  // The reference does this whole computation in float32, with the intrinsics rounded to float32.
  const float fx = static_cast<float>(intrinsics.fx);
  const float fy = static_cast<float>(intrinsics.fy);
  const float cx = static_cast<float>(intrinsics.cx);
  const float cy = static_cast<float>(intrinsics.cy);
  if (distorted()) {
    rays_.resize(std::size_t(rows) * cols);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c)
        rays_[std::size_t(r) * cols + c] = Eigen::Vector2d(c * grid.stride, r * grid.stride);
    }
    intrinsics.normalisedRays(rays_);
  }
  for (int r = 0; r < rows; ++r) {
    const float v = static_cast<float>(r * grid.stride);
    float y_n = (cy - v) / fy;
    float min_el = INFINITY;
    float max_el = -INFINITY;
    for (int c = 0; c < cols; ++c) {
      const float u = static_cast<float>(c * grid.stride);
      float x_n = (u - cx) / fx;
      if (!rays_.empty()) {
        const Eigen::Vector2d& ray = rays_[std::size_t(r) * cols + c];
        x_n = static_cast<float>(ray.x());
        y_n = static_cast<float>(-ray.y());  // elevation counts up, image y down
      }
      const float norm = std::sqrt(x_n * x_n + y_n * y_n + 1.0f);
      const float dx = x_n / norm;
      const float dy = y_n / norm;
      const float dz = 1.0f / norm;
      const float az = std::atan2(dx, dz) * kRadToDeg32;
      const float el = std::atan2(dy, std::sqrt(dx * dx + dz * dz)) * kRadToDeg32;
      azimuth_[std::size_t(r) * cols + c] = az;
      elevation_[std::size_t(r) * cols + c] = el;
      min_el = std::min(min_el, el);
      max_el = std::max(max_el, el);
    }
    row_min_elevation_[r] = min_el;
    row_max_elevation_[r] = max_el;
  }
  // Azimuth is atan(x_n) whatever the row, but float32 rounding differs per row: envelopes over all
  // rows, made monotone, bound every row at once.
  column_azimuth_upper_.assign(cols, -INFINITY);
  column_azimuth_lower_.assign(cols, INFINITY);
  for (int r = 0; r < rows; ++r) {
    const float* az = azimuthRow(r);
    for (int c = 0; c < cols; ++c) {
      column_azimuth_upper_[c] = std::max(column_azimuth_upper_[c], az[c]);
      column_azimuth_lower_[c] = std::min(column_azimuth_lower_[c], az[c]);
    }
  }
  for (int c = 1; c < cols; ++c) {
    column_azimuth_upper_[c] = std::max(column_azimuth_upper_[c], column_azimuth_upper_[c - 1]);
  }
  for (int c = cols - 2; c >= 0; --c) {
    column_azimuth_lower_[c] = std::min(column_azimuth_lower_[c], column_azimuth_lower_[c + 1]);
  }
}

std::pair<int, int> PixelAngleGrid::columnRange(float az_low, float az_high) const {
  // First column that some row reaches az_low in, and first column every row is past az_high in.
  const auto first =
      std::lower_bound(column_azimuth_upper_.begin(), column_azimuth_upper_.end(), az_low);
  const auto last =
      std::upper_bound(column_azimuth_lower_.begin(), column_azimuth_lower_.end(), az_high);
  return {static_cast<int>(first - column_azimuth_upper_.begin()),
          static_cast<int>(last - column_azimuth_lower_.begin())};
}

AngularBox PixelAngleGrid::extent() const {
  const int cols = grid_.cols();
  AngularBox box{INFINITY, -INFINITY, INFINITY, -INFINITY};
  for (int r = 0; r < grid_.rows(); ++r) {
    const float* az = azimuthRow(r);
    box.az_min = std::min({box.az_min, az[0], az[cols - 1]});
    box.az_max = std::max({box.az_max, az[0], az[cols - 1]});
    if (distorted()) {  // a distorted row's azimuth need not be extreme at its ends
      const auto [low, high] = std::minmax_element(az, az + cols);
      box.az_min = std::min(box.az_min, *low);
      box.az_max = std::max(box.az_max, *high);
    }
    box.el_min = std::min(box.el_min, row_min_elevation_[r]);
    box.el_max = std::max(box.el_max, row_max_elevation_[r]);
  }
  return box;
}

bool PixelAngleGrid::matches(const PinholeIntrinsics& k, const StrideGrid& grid) const {
  return grid_ == grid && intrinsics_.fx == k.fx && intrinsics_.fy == k.fy &&
         intrinsics_.cx == k.cx && intrinsics_.cy == k.cy && intrinsics_.distortion == k.distortion;
}

Eigen::Vector2d PixelAngleGrid::normalisedRay(int row, int col) const {
  if (!rays_.empty()) return rays_[std::size_t(row) * grid_.cols() + col];
  return {(double(col) * grid_.stride - intrinsics_.cx) / intrinsics_.fx,
          (double(row) * grid_.stride - intrinsics_.cy) / intrinsics_.fy};
}

}  // namespace multimodal_nvs
