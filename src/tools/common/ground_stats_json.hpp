#pragma once
// The ground plane and mode of a depth map's stats as every depth tool prints them, so that
// complete_depth's stats line and evaluate_depth's per-frame entries carry the same fields.
#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"

namespace multimodal_nvs {
namespace cli {

/// Adds ground_source, ground_mode, the fit's shares, the hidden returns, the edge ratio and the
/// plane used (camera height, pitch, roll) to `out`; nothing for a model without a ground plane
/// (ground_mode empty).
void addGroundStats(const DepthMapStats& stats, json::Json& out);

}  // namespace cli
}  // namespace multimodal_nvs
