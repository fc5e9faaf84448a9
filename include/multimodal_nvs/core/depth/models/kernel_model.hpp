#pragma once
// `kernel`: the reference's fast mode, Gaussian kernel regression within the radius.
#include <vector>
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/neighbour_sets.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// Gaussian kernel regression within the radius (reference `kernel`, kernel_regression.cpp); no
/// neighbour: no prediction.
void predictKernel(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                   const NeighbourSets& sets, const DepthCompletionParams& params, double shift,
                   ThreadPool& pool, PixelPredictions& out);

}  // namespace multimodal_nvs
