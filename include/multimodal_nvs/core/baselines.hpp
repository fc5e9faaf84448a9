#pragma once
// Baseline depth-completion models the local GP is measured against (issue 6). Each writes the
// same per-pixel output as the GP models — mean in metres, variance in m^2, +inf (and a NaN mean)
// where it makes no prediction — so retention, the tools and the nodelet treat them alike.
//
// Every baseline uses only the usable samples: finite angles and a finite camera depth > 0.
// Points behind the camera (depth <= 0) are dropped; a depth-completion model must not predict a
// negative depth from them. (The GP models keep them in the shift median, as the reference does.)
#include <vector>

#include "multimodal_nvs/core/angular_projection.hpp"
#include "multimodal_nvs/core/depth_models.hpp"
#include "multimodal_nvs/core/depth_params.hpp"
#include "multimodal_nvs/core/thread_pool.hpp"

namespace multimodal_nvs {

/// True for nearest, linear, ipbasic and constant.
bool isBaseline(DepthModel model);

/// Runs the baseline `params.model` (throws InputError for a GP model).
void predictBaseline(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out);

/// `nearest`: the depth of the angularly nearest usable sample (Euclidean distance in degree space,
/// no radius limit; ties: the lower sample index). Variance: distanceVariance(d) of the distance d
/// to that sample. Exact at a sample's own direction.
void predictNearest(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                    const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out);

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
void predictIpBasic(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                    const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out);
constexpr double kIpBasicReferenceSpacing = 4.0;

/// `constant`: the median depth of the usable samples that project into the image (of all usable
/// samples when none does; numpy's median) at every pixel. Variance: the sample variance of those
/// depths (ddof = 1; 0 for a single sample). No usable sample: no prediction.
void predictConstant(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out);

/// The variance nearest and ipbasic assign at angular distance d (deg) from the sample they copy:
///   sigma^2 + a^2 d^2 / l^2,  sigma = params.gp.noise, a = params.gp.amplitude,
///   l = params.kernel_length_scale_deg (defaults: 0.25 + 1111 d^2 m^2 with d in degrees).
/// It is the small-distance behaviour of a one-sample GP with the package's amplitude, noise and
/// the kernel model's length scale (posterior variance ~ sigma^2 + a^2 d^2 / l^2 for d << l), kept
/// growing instead of saturating at the prior a^2 so that retention ranks every pixel by its
/// distance to the data (a saturating variance would tie most radar pixels at the prior).
double distanceVariance(double distance_deg, const DepthCompletionParams& params);

/// Samples with finite angles and a finite depth > 0, in their original order.
std::vector<AngularSample> usableSamples(const std::vector<AngularSample>& samples);

/// Continuous full-image pixel position (u, v) of the direction (az, el) in degrees — the inverse
/// of the pixel-angle convention: u = cx + fx tan(az), v = cy - fy tan(el) / cos(az). Returns false
/// for directions at or beyond 90 deg from the optical axis.
bool angularToPixel(const PinholeIntrinsics& k, double azimuth_deg, double elevation_deg, double* u,
                    double* v);

}  // namespace multimodal_nvs
