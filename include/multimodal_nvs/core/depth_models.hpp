#pragma once
#include <limits>
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

/// Variance of a pixel that got no prediction.
constexpr float kNoPrediction = std::numeric_limits<float>::infinity();

/// Sizes `out` to the grid and sets every pixel to (mean, variance), in parallel: the buffers are
/// reused across frames, so this is one full-image pass shared by both cores, not an allocation.
void fillPredictions(const PixelAngleGrid& angles, float mean, float variance, ThreadPool& pool,
                     PixelPredictions& out);

/// The GP's prior mean: a constant (the reference's shift). A per-pixel prior (ground_gp) is added
/// by the caller in its own final pass over the image, which saves copying it into the output.
struct PriorMean {
  double constant = 0.0;
};

/// Exact local GP with marginal-likelihood length scale (reference `local_gp_mle`). Pixels without
/// a neighbour, or whose final Cholesky fails, get mean = shift and variance = a^2.
void predictLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                    const NeighbourSets& sets, const DepthCompletionParams& params, double shift,
                    ThreadPool& pool, PixelPredictions& out);

/// The same GP on explicit targets (sample depth minus the prior at the sample) around a prior mean:
/// mean = prior + k*^T K^-1 y. With a constant prior c and targets z - c it is the model above.
void predictLocalGp(const std::vector<AngularSample>& samples, const std::vector<double>& targets,
                    const PixelAngleGrid& angles, const NeighbourSets& sets,
                    const DepthCompletionParams& params, const PriorMean& prior, ThreadPool& pool,
                    PixelPredictions& out);

/// Gaussian kernel regression within the radius (reference `kernel`, kernel_regression.cpp); no
/// neighbour: no prediction.
void predictKernel(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                   const NeighbourSets& sets, const DepthCompletionParams& params, double shift,
                   ThreadPool& pool, PixelPredictions& out);

struct GroundPlane;
/// `ground_gp`: local GP on the residual around the ground-plane prior (ground_gp_model.cpp).
void predictGroundGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const NeighbourSets& sets, const DepthCompletionParams& params,
                     const GroundPlane& plane, double median_depth, ThreadPool& pool,
                     PixelPredictions& out);

/// `ground_gp` on dense input (ground_gp_model.cpp): the prior is the edge-aware interpolation of
/// inverse depth on the Delaunay triangulation of the samples; no residual GP (the prior already
/// passes through every sample, so the GP's posterior mean would equal it).
void predictGroundGpDense(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                          const DepthCompletionParams& params, const GroundPlane& plane,
                          double median_depth, ThreadPool& pool, PixelPredictions& out);

/// Whether `ground_gp` runs its dense-input mode: params.ground.input, or for auto whether the mean
/// angular spacing sqrt(view area / samples in view) is at most half of params.radius_deg.
bool groundInputIsDense(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params);

/// The documented approximation for dense input (max_neighbors > 0): one neighbour set of at most
/// max_neighbors samples and one length scale per tile. Returns the number of tiles solved.
int predictTiledLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, double shift, ThreadPool& pool,
                        PixelPredictions& out);

/// Targets y = float32(z) - float32(shift) in float32, promoted to double (reference arithmetic).
std::vector<double> shiftedTargets(const std::vector<AngularSample>& samples, double shift);

}  // namespace multimodal_nvs
