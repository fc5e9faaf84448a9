#pragma once
// The tiled approximation of `local_gp_mle` for dense input (max_neighbors > 0).
#include <vector>
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// The documented approximation for dense input (max_neighbors > 0): one neighbour set of at most
/// max_neighbors samples and one length scale per tile. Returns the number of tiles solved.
int predictTiledLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, double shift, ThreadPool& pool,
                        PixelPredictions& out);

}  // namespace multimodal_nvs
