#pragma once
// A prediction made on a coarser grid, interpolated onto the output grid.
#include <vector>

#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"

namespace multimodal_nvs {

/// `coarse` lives on `coarse_grid`, whose stride is `factor` times `grid`'s (same image): output
/// pixel (r, c) lies at (r / factor, c / factor) of the coarse grid. Writes `out` on `grid` by
/// bilinear interpolation, of inverse depth for the mean (affine in the image along a plane, the
/// road; depth is not) and of the variance; past the coarse grid's last row or column the edge
/// value holds. `scratch`: a buffer reused across calls. The coarse means must be > 0.
void upsamplePredictions(const PixelPredictions& coarse, const StrideGrid& coarse_grid,
                         const StrideGrid& grid, int factor, ThreadPool& pool,
                         std::vector<float>& scratch, PixelPredictions& out);

}  // namespace multimodal_nvs
