#pragma once
// A prediction made on a coarser grid, interpolated onto the output grid, and a prediction read a
// row at a time whether it was stored on the output grid or is interpolated when read.
#include <vector>

#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"

namespace multimodal_nvs {

/// `coarse` on `coarse_grid`, whose stride is `factor` times `grid`'s (same image): output pixel
/// (r, c) lies at (r / factor, c / factor) of the coarse grid. Output rows by bilinear
/// interpolation, of inverse depth for the mean (affine in the image along a plane, the road;
/// depth is not) and of the variance; past the coarse grid's last row or column the edge value
/// holds. The coarse means must be > 0. Each row is interpolated when it is read, so a caller
/// that consumes the prediction row by row never holds (nor writes and reads back) the two
/// full-size planes: 19 MB at VoD's 1936x1216.
class UpsampledPredictions {
 public:
  /// Spreads every coarse row over the output columns (the index gathers run on `factor` times
  /// fewer rows than the output has); the buffers are kept for the next call.
  void prepare(const PixelPredictions& coarse, const StrideGrid& coarse_grid,
               const StrideGrid& grid, int factor, ThreadPool& pool);
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  /// Output row `row`'s means (cols() floats) into `out`.
  void meanRow(int row, float* out) const;
  /// Output row `row`'s variances (cols() floats) into `out`.
  void varianceRow(int row, float* out) const;

 private:
  int rows_ = 0, cols_ = 0, coarse_rows_ = 0, factor_ = 1;
  std::vector<float> wide_inverse_, wide_variance_;  // coarse rows x output columns
};

/// UpsampledPredictions' rows, all of them, into `out` (sized to `grid`).
void upsamplePredictions(const PixelPredictions& coarse, const StrideGrid& coarse_grid,
                         const StrideGrid& grid, int factor, ThreadPool& pool,
                         PixelPredictions& out);

/// A prediction on the output grid read row by row: stored (a PixelPredictions of rows x cols) or
/// interpolated from a coarser grid as each row is read (UpsampledPredictions). Both outlive it.
class PredictionRows {
 public:
  /// Throws std::invalid_argument when `stored` does not hold rows x cols means and variances.
  PredictionRows(const PixelPredictions& stored, int rows, int cols);
  explicit PredictionRows(const UpsampledPredictions& upsampled);
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  /// Row `row`'s means: a pointer into the stored prediction, or `scratch` (cols() floats) filled.
  const float* mean(int row, float* scratch) const;
  /// Row `row`'s variances, as mean().
  const float* variance(int row, float* scratch) const;

 private:
  const PixelPredictions* stored_ = nullptr;
  const UpsampledPredictions* upsampled_ = nullptr;
  int rows_, cols_;
};

}  // namespace multimodal_nvs
