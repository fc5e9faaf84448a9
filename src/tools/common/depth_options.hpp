#pragma once
// The depth-model options shared by every tool that runs depth completion (complete_depth,
// evaluate_depth): one declaration and one mapping onto DepthCompletionParams.
#include <string>

#include "cli.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"

namespace multimodal_nvs {
namespace cli {

/// Declares --model, --radius-deg, the GP, kernel, shift, threshold, approximation, thread and
/// ground_gp options with the reference defaults. Retention and the grid belong to each tool.
void declareDepthModelOptions(Args& args);

/// DepthCompletionParams from those options (retain_percent stays 100). Throws UsageError or
/// InputError.
DepthCompletionParams depthModelParams(const Args& args);

/// ground_gp: takes the ground plane from a VoD pose file (--ground-pose, or `default_pose` when
/// that is empty and exists). Does nothing for other models or without a pose.
void applyGroundPose(const Args& args, const std::string& default_pose, DepthCompletionParams& p);

}  // namespace cli
}  // namespace multimodal_nvs
