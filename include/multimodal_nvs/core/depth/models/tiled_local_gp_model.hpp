#pragma once
// The tiled approximation of `local_gp_mle` for dense input (max_neighbors > 0).
#include <vector>
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/gp/gp_prediction.hpp"
#include "multimodal_nvs/core/depth/models/local_gp_model.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// The documented approximation for dense input (max_neighbors > 0): one neighbour set of at most
/// max_neighbors samples and one length scale per tile. Returns the number of tiles solved.
int predictTiledLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, double shift, ThreadPool& pool,
                        PixelPredictions& out);

/// The same approximation on explicit targets around a prior mean (as the second predictLocalGp):
/// ground_gp's residual GP when its neighbour sets are large. `precision`: of the length-scale
/// searches' likelihood and of the per-pixel step (the factors stay double), as in predictLocalGp.
int predictTiledLocalGp(const std::vector<AngularSample>& samples,
                        const std::vector<double>& targets, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, const PriorMean& prior,
                        ThreadPool& pool, PixelPredictions& out,
                        PredictionPrecision precision = PredictionPrecision::kDouble);

/// Mean number of samples (itself included) within params.radius_deg of a sample in view: the
/// mean size of the neighbour sets near the returns. VoD and nuScenes radar: 5-9; Astyx 6455
/// imaging radar: 20-60; 1-in-4 LiDAR: hundreds.
double meanSamplesWithinRadius(const std::vector<AngularSample>& samples,
                               const PixelAngleGrid& angles, const DepthCompletionParams& params);

/// Above this mean (meanSamplesWithinRadius), ground_gp with max_neighbors = 0 solves its residual
/// GP with the tile approximation: the exact method's distinct sets number in the tens of
/// thousands there (Astyx: 22-70 k at 2048x618, against 3.9 k on VoD) with dozens of samples each.
constexpr double kLargeNeighbourSetMean = 12.0;

}  // namespace multimodal_nvs
