#pragma once
// `constant`: the median depth everywhere.
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

/// `constant`: the median depth of the usable samples that project into the image (of all usable
/// samples when none does; numpy's median) at every pixel. Variance: the sample variance of those
/// depths (ddof = 1; 0 for a single sample). No usable sample: no prediction.
void predictConstant(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out);

}  // namespace multimodal_nvs
