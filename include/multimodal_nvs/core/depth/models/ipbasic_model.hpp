#pragma once
// `ipbasic`: classical morphological completion (Ku et al. 2018, "In Defense of Classical Image
// Processing").
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

/// `ipbasic`: classical image-processing completion in the spirit of Ku et al. 2018 ("In Defense
/// of Classical Image Processing", the fast variant), on the sparse depth image of the usable
/// samples projected onto the stride grid (nearest return per grid pixel):
///   invert (offset - z, offset = max depth + 1 m so no depth is lost), dilate with a diamond,
///   morphological closing, fill empty pixels from a full-kernel dilation, extend each column's
///   topmost value to the top row, fill the remaining large holes from a wide dilation, 5x5 median,
///   5x5 bilateral (sigma colour 1.5 m, sigma space 2 px), re-invert.
/// The published kernels (diamond 5, full 5, 7 and 31 px) are tuned for KITTI's HDL-64 image, whose
/// projected returns are about kIpBasicReferenceSpacing px apart (~19k returns over the lower
/// ~1242x235 px of the image; our estimate). They are scaled by the measured
/// spacing of the input (sqrt(area of the rows holding samples / occupied pixels)) divided by that
/// value, clamped to [0.5, 8], so radar, LiDAR, subsampled LiDAR and every stride get comparable
/// fills. Meant for LiDAR input; on radar it degenerates into wide max-filters.
/// Variance: distanceVariance(d) with d the distance to the nearest projected sample in grid
/// pixels converted to degrees at the image centre (stride * 180 / (pi fx)). Pixels still empty at
/// the end (e.g. no sample at all): no prediction.
/// Memory: besides the output, each calling thread keeps four grid-sized scratch images across
/// frames (3 float, 1 int32; ~38 MB at 1936x1216, stride 1) so that frames reuse warm pages.
void predictIpBasic(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                    const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out);
constexpr double kIpBasicReferenceSpacing = 4.0;

}  // namespace multimodal_nvs
