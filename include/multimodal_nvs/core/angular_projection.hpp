#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/camera.hpp"

namespace multimodal_nvs {

/// A range sample expressed in the angular domain of the camera (degrees, elevation positive up)
/// with its camera-z depth. Angles are float32 because the reference stores them that way and the
/// neighbourhood test must see the very same values.
struct AngularSample {
  float azimuth_deg;
  float elevation_deg;
  float depth;
};

/// Camera-frame points -> angular samples: az = atan2(x, z), el = atan2(-y, hypot(x, z)), computed
/// in double and rounded to float32 (the reference's convention). Non-finite points are skipped and
/// counted in `dropped_non_finite` when it is not null.
std::vector<AngularSample> toAngularSamples(const std::vector<Eigen::Vector3d>& points_camera,
                                            std::size_t* dropped_non_finite = nullptr);

/// Transforms sensor-frame points into the camera frame (double precision, like the reference).
std::vector<Eigen::Vector3d> transformToCamera(const std::vector<Eigen::Vector3f>& points_sensor,
                                               const SensorToCamera& sensor_to_camera);

/// Output raster: pixel centres u = 0, s, 2s, ... and v = 0, s, 2s, ... of the full image (no
/// +0.5), shape ceil(H/s) x ceil(W/s); intrinsics are not rescaled.
struct StrideGrid {
  ImageSize image;
  int stride = 1;
  int rows() const { return (image.height + stride - 1) / stride; }
  int cols() const { return (image.width + stride - 1) / stride; }
  long long size() const { return static_cast<long long>(rows()) * cols(); }
  bool operator==(const StrideGrid& o) const { return image == o.image && stride == o.stride; }
};

/// An axis-aligned box in the angular domain (degrees).
struct AngularBox {
  float az_min, az_max, el_min, el_max;
};

/// Azimuth/elevation of every grid pixel's ray, row-major, computed in float32 exactly as the
/// reference does (normalised ray, atan2f, degrees). Depends only on intrinsics and grid, so a node
/// computes it once per camera and reuses it for every scan.
class PixelAngleGrid {
 public:
  PixelAngleGrid() = default;
  PixelAngleGrid(const PinholeIntrinsics& intrinsics, const StrideGrid& grid);

  const StrideGrid& grid() const { return grid_; }
  const PinholeIntrinsics& intrinsics() const { return intrinsics_; }
  const float* azimuthRow(int row) const {
    return azimuth_.data() + std::size_t(row) * grid_.cols();
  }
  const float* elevationRow(int row) const {
    return elevation_.data() + std::size_t(row) * grid_.cols();
  }
  float minElevation(int row) const { return row_min_elevation_[row]; }
  float maxElevation(int row) const { return row_max_elevation_[row]; }
  /// Columns [first, second) outside of which every row's azimuth is below `az_low` or above
  /// `az_high`. Exact for the float32 grid (monotone envelopes over all rows), so a search by
  /// azimuth needs one lookup per sample instead of one per sample and row.
  std::pair<int, int> columnRange(float az_low, float az_high) const;
  /// The box holding every pixel's angles (azimuth is extreme in the first and last column).
  AngularBox extent() const;
  bool matches(const PinholeIntrinsics& intrinsics, const StrideGrid& grid) const;

 private:
  PinholeIntrinsics intrinsics_;
  StrideGrid grid_;
  std::vector<float> azimuth_;
  std::vector<float> elevation_;
  std::vector<float> row_min_elevation_;
  std::vector<float> row_max_elevation_;
  std::vector<float> column_azimuth_upper_;  // max over rows and columns <= c (non-decreasing)
  std::vector<float> column_azimuth_lower_;  // min over rows and columns >= c (non-decreasing)
};

}  // namespace multimodal_nvs
