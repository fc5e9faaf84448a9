#pragma once
// `local_gp_mle`: the exact localized GP of the paper (reference parity), per neighbour set.
#include <functional>
#include <vector>
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/gp/gp_prediction.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/neighbour_sets.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// The GP's prior mean: a constant (the reference's shift). A per-pixel prior (ground_gp) is added
/// by the caller (see `finish_row` below), which saves copying it into the output.
struct PriorMean {
  double constant = 0.0;
};

/// Exact local GP with marginal-likelihood length scale (reference `local_gp_mle`). Pixels without
/// a neighbour, or whose final Cholesky fails, get mean = shift and variance = a^2.
void predictLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                    const NeighbourSets& sets, const DepthCompletionParams& params, double shift,
                    ThreadPool& pool, PixelPredictions& out);

/// The same GP on explicit targets (sample depth minus the prior at the sample) around a prior
/// mean: mean = prior + k*^T K^-1 y. With a constant prior c and targets z - c it is the model
/// above. `precision`: of the length-scale search's likelihood (sets of 3..32 samples) and of the
/// per-pixel step; the sets' factors stay double.
/// `finish_row(row)`, when given, runs on the worker right after the row's pixels are written,
/// while they are still in cache: a caller's per-pixel pass over the GP's output (ground_gp adds
/// its prior there) then costs no second trip through memory.
void predictLocalGp(const std::vector<AngularSample>& samples, const std::vector<double>& targets,
                    const PixelAngleGrid& angles, const NeighbourSets& sets,
                    const DepthCompletionParams& params, const PriorMean& prior, ThreadPool& pool,
                    PixelPredictions& out,
                    PredictionPrecision precision = PredictionPrecision::kDouble,
                    const std::function<void(int row)>& finish_row = nullptr);

/// Targets y = float32(z) - float32(shift) in float32, promoted to double (reference arithmetic).
std::vector<double> shiftedTargets(const std::vector<AngularSample>& samples, double shift);

}  // namespace multimodal_nvs
