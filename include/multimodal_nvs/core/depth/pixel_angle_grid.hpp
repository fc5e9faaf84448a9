#pragma once
// The viewing direction of every output pixel in the angular domain, computed once per camera.
#include <utility>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"

namespace multimodal_nvs {

/// Azimuth/elevation of every grid pixel's ray, row-major, computed in float32 exactly as the
/// reference does (normalised ray, atan2f, degrees). Depends only on intrinsics and grid, so a node
/// computes it once per camera and reuses it for every scan. With lens distortion each pixel's ray
/// is undistorted once here (the angular models then need no per-frame camera model at all) and
/// kept, so that stages working in normalised coordinates read it instead of dividing by K.
class PixelAngleGrid {
 public:
  PixelAngleGrid() = default;
  PixelAngleGrid(const PinholeIntrinsics& intrinsics, const StrideGrid& grid);

  /// A row pointer may be read up to this many floats past the row's last pixel (into the next
  /// row, and after the last row into zero padding): vector loops over a span of a row then run
  /// in whole blocks, without a scalar remainder (most spans a rasteriser visits are shorter than
  /// one block of the vectorised loop, which left nearly all the work to the remainder).
  static constexpr int kRowReadPadding = 16;

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
  bool distorted() const { return intrinsics_.distortion.any(); }
  /// The undistorted normalised ray (x = X/Z, y = Y/Z, y down) of grid pixel (row, col): read from
  /// the table for a distorted camera, the pinhole division otherwise.
  Eigen::Vector2d normalisedRay(int row, int col) const;

 private:
  PinholeIntrinsics intrinsics_;
  StrideGrid grid_;
  std::vector<float> azimuth_;
  std::vector<float> elevation_;
  std::vector<float> row_min_elevation_;
  std::vector<float> row_max_elevation_;
  std::vector<float> column_azimuth_upper_;  // max over rows and columns <= c (non-decreasing)
  std::vector<float> column_azimuth_lower_;  // min over rows and columns >= c (non-decreasing)
  std::vector<Eigen::Vector2d> rays_;        // undistorted normalised rays; distorted cameras only
};

}  // namespace multimodal_nvs
