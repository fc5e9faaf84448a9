#pragma once
// Where a sensor's returns stop: the top of the band of elevations they cover. A radar's vertical
// field of view is narrow (VoD's returns end about 3 degrees above the optical axis, 45 % of
// the way down the image), so above that band the image shows surfaces no return measured.
#include <vector>

namespace multimodal_nvs {

/// The share of the returns allowed above the band's top: a few clutter or multipath returns high
/// up do not lift it.
inline constexpr double kReturnBandTopShare = 0.02;

/// The elevation (degrees) that all but `top_share` of `elevations` lie at or below: the value of
/// rank floor(top_share * n) from the top. NaN for no elevations. Takes its argument by value (it
/// reorders it).
float returnBandTop(std::vector<float> elevations, double top_share = kReturnBandTopShare);

}  // namespace multimodal_nvs
