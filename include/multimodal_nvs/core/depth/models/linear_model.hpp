#pragma once
// `linear`: barycentric interpolation on the angular Delaunay triangulation.
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

/// `linear`: Delaunay triangulation of the usable samples in (azimuth, elevation) and barycentric
/// interpolation of their depths; exact wherever depth is an affine function of the angles.
/// Outside the convex hull: no prediction. Samples with identical angles keep the nearest depth.
/// Only samples within 10% of the image's angular extent (at least 2 deg) around it are
/// triangulated, so 360-degree LiDAR does not pay for points far outside the view.
/// Variance: the barycentric-weighted second central moment of the triangle's three depths,
/// sum_i l_i (z_i - mean)^2 — the kernel model's definition with barycentric weights: 0 at a
/// sample and inside flat triangles, large across depth discontinuities.
void predictLinear(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                   const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out);

}  // namespace multimodal_nvs
