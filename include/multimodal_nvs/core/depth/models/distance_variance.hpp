#pragma once
// The variance of a copied depth as a function of the angular distance to its return.
#include "multimodal_nvs/core/depth/depth_params.hpp"

namespace multimodal_nvs {

/// The variance nearest and ipbasic assign at angular distance d (deg) from the sample they copy:
///   sigma^2 + a^2 d^2 / l^2,  sigma = params.gp.noise, a = params.gp.amplitude,
///   l = params.kernel_length_scale_deg (defaults: 0.25 + 1111 d^2 m^2 with d in degrees).
/// It is the small-distance behaviour of a one-sample GP with the package's amplitude, noise and
/// the kernel model's length scale (posterior variance ~ sigma^2 + a^2 d^2 / l^2 for d << l), kept
/// growing instead of saturating at the prior a^2 so that retention ranks every pixel by its
/// distance to the data (a saturating variance would tie most radar pixels at the prior).
/// Inline: it runs once per pixel in the `ipbasic` and `nearest` output passes, where a call per
/// pixel kept the loops from being vectorised.
inline double distanceVariance(double distance_deg, const DepthCompletionParams& params) {
  const double sigma = params.gp.noise, a = params.gp.amplitude;
  const double l = params.kernel_length_scale_deg;
  const double ratio = distance_deg / l;
  return sigma * sigma + a * a * ratio * ratio;
}

}  // namespace multimodal_nvs
