#pragma once
#include <vector>

#include "multimodal_nvs/core/angular_projection.hpp"
#include "multimodal_nvs/core/depth_params.hpp"
#include "multimodal_nvs/core/neighbour_sets.hpp"
#include "multimodal_nvs/core/thread_pool.hpp"

namespace multimodal_nvs {

/// Per-pixel prediction written by a model: mean (metres) and variance (m^2, +inf = no prediction).
struct PixelPredictions {
  std::vector<float> mean;
  std::vector<float> variance;
};

/// Exact local GP with marginal-likelihood length scale (reference `local_gp_mle`). Pixels without
/// a neighbour, or whose final Cholesky fails, get mean = shift and variance = a^2.
void predictLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                    const NeighbourSets& sets, const DepthCompletionParams& params, double shift,
                    ThreadPool& pool, PixelPredictions& out);

/// Gaussian kernel regression within the radius (reference `kernel`); no neighbour: no prediction.
void predictKernel(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                   const NeighbourSets& sets, const DepthCompletionParams& params, double shift,
                   ThreadPool& pool, PixelPredictions& out);

/// The documented approximation for dense input (max_neighbors > 0): one neighbour set of at most
/// max_neighbors samples and one length scale per tile. Returns the number of tiles solved.
int predictTiledLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, double shift, ThreadPool& pool,
                        PixelPredictions& out);

/// Targets y = float32(z) - float32(shift) in float32, promoted to double (reference arithmetic).
std::vector<double> shiftedTargets(const std::vector<AngularSample>& samples, double shift);

}  // namespace multimodal_nvs
