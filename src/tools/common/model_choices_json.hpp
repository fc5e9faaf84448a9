#pragma once
// What a model chose for a frame, from a depth map's stats, as every depth tool prints it, so that
// complete_depth's stats line and evaluate_depth's per-frame entries carry the same fields.
#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"

namespace multimodal_nvs {
namespace cli {

/// Adds to `out`, for a model with a ground plane (ground_mode not empty), ground_source,
/// ground_mode, the fit's shares, the hidden returns, the edge ratio, whether the returns lie on
/// one scan plane and the plane used (camera height, pitch, roll); for image_guided also
/// guided_return_density, guided_prior_weight and, where the prior weighed more above the
/// returns' band, guided_band_top_deg. Nothing for the other models.
void addModelChoices(const DepthMapStats& stats, json::Json& out);

}  // namespace cli
}  // namespace multimodal_nvs
