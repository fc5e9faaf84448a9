#pragma once
// `nearest`: the depth of the angularly nearest return.
// A baseline the local GP is measured against. Like the GP models it writes the mean in metres and
// the variance in m^2, +inf (and a NaN mean) where it makes no prediction, so retention, the tools
// and the nodelet treat it alike. It uses only the usable samples (usableSamples): points behind
// the camera are dropped, a depth-completion model must not predict a negative depth from them.
#include <vector>
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// `nearest`: the depth of the angularly nearest usable sample (Euclidean distance in degree space,
/// no radius limit; ties: the lower sample index). Variance: distanceVariance(d) of the distance d
/// to that sample. Exact at a sample's own direction.
void predictNearest(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                    const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out);

/// The index into `samples` of each grid pixel's angularly nearest sample (row-major; ties: the
/// lower index), -1 everywhere when there is none: the sample predictNearest() takes its depth
/// from, for models that need more of it than the depth. `samples` are used as they are: pass
/// usableSamples() for predictNearest()'s choice.
std::vector<int> nearestSampleIndex(const std::vector<AngularSample>& samples,
                                    const PixelAngleGrid& angles, ThreadPool& pool);

}  // namespace multimodal_nvs
