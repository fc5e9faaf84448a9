#pragma once
// How densely the returns cover the camera's view, and the weight of image_guided's prior that
// follows from it.
#include <cstddef>

#include "multimodal_nvs/core/common/camera.hpp"

namespace multimodal_nvs {

/// The image's extent in azimuth times its extent in elevation, square degrees, through the
/// pinhole model along the principal point's row and column (pixel edges -0.5 .. size - 0.5). For
/// View-of-Delft's camera 2,913, Astyx's 1,135, a 1,600x900 nuScenes camera ~2,530. A property of
/// the camera, not of the output grid: PixelAngleGrid::extent() is the bounding box of the grid's
/// pixel centres, which shrinks with the stride and widens with the rows' curvature.
double viewSquareDegrees(const PinholeIntrinsics& intrinsics, const ImageSize& image);

/// Returns per square degree of the view (0 for an empty view).
double returnDensity(std::size_t returns_in_view, const PinholeIntrinsics& intrinsics,
                     const ImageSize& image);

/// The smallest and largest factor priorWeightForDensity applies. Below: a frame with almost no
/// returns in view keeps a quarter of the prior's weight (the returns it has still count). Above:
/// ten times the reference is the densest radar measured (Astyx, 0.96 returns per square degree);
/// a far denser scan in the sparse mode (a LiDAR forced to it) would otherwise bury its returns
/// under the prior.
inline constexpr double kMinPriorWeightFactor = 0.25;
inline constexpr double kMaxPriorWeightFactor = 10.0;

/// image_guided's prior weight for a frame whose returns have `density` (per square degree):
/// `weight` times density / `reference_density`, the factor held within [kMinPriorWeightFactor,
/// kMaxPriorWeightFactor]; `weight` itself when reference_density is 0. The smoother's evidence
/// at a pixel is the prior's weight against the returns it reaches, so at a fixed weight a denser
/// sensor hands the depth to the mean of more returns; ground_gp's prior (a low order statistic of
/// the nearest returns) sharpens with the density instead, and a radar's extra returns are often
/// behind the surface (ImageGuidedParams::prior_reference_density).
double priorWeightForDensity(double weight, double density, double reference_density);

}  // namespace multimodal_nvs
