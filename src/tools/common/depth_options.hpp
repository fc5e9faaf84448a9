#pragma once
// The depth-model options shared by every tool that runs depth completion (complete_depth,
// evaluate_depth): one declaration and one mapping onto DepthCompletionParams.
#include <string>

#include "cli.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"

namespace multimodal_nvs {
namespace cli {

/// What the options bind to: the numeric parameters directly, the named choices as text.
struct DepthModelOptions {
  DepthCompletionParams params;
  std::string model = "local_gp_mle", shift = "median", ground_input = "auto";
  std::string ground_pose;
  std::string pose_key = io::odometryVodPoseKey();
  double camera_pitch_deg = 0.0;  ///< without a pose (GroundPriorParams::setPitchDeg)
};

/// Declares --model, --radius-deg, the GP, kernel, shift, threshold, approximation, thread and
/// ground_gp options with the reference defaults. Retention and the grid belong to each tool.
void declareDepthModelOptions(CLI::App& app, DepthModelOptions& options);

/// DepthCompletionParams from those options (retain_percent stays 100). Throws UsageError or
/// InputError.
DepthCompletionParams depthModelParams(const DepthModelOptions& options);

/// ground_gp: takes the ground plane from a VoD pose file (--ground-pose, or `default_pose` when
/// that is empty and exists). Without either the model keeps its pose-free ground (a missing
/// default pose is not an error); an explicit --ground-pose that cannot be read is.
void applyGroundPose(const DepthModelOptions& options, const std::string& default_pose,
                     DepthCompletionParams& p);

}  // namespace cli
}  // namespace multimodal_nvs
