#pragma once
// The virtual cameras of a burst or an export on tf, so that rviz shows the trajectory and
// downstream nodes can use the views: `conditioning_keyframe` is the keyframe camera where the
// keyframe was taken (a child of world_frame at the keyframe's pose when that is known, else of the
// camera frame itself), and view i is `conditioning_view_NNN` (three digits), its child.
#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <std_msgs/Header.h>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "multimodal_nvs/core/render/trajectory.hpp"

namespace multimodal_nvs {

constexpr char kKeyframeViewFrame[] = "conditioning_keyframe";

/// "conditioning_view_007" for view 7.
std::string virtualViewFrame(int index);

/// The keyframe frame and every view of `trajectory` as transforms stamped with the keyframe's
/// stamp: keyframe_header.frame_id is the camera; `keyframe_in_world` its pose in `world_frame`
/// (nullopt: the keyframe frame is the camera frame itself, identity).
std::vector<geometry_msgs::TransformStamped> virtualViewTransforms(
    const Trajectory& trajectory, const std_msgs::Header& keyframe_header,
    const std::optional<Eigen::Matrix4d>& keyframe_in_world, const std::string& world_frame);

/// The views of virtualViewTransforms' result (every transform but the keyframe's) as one pose
/// array in conditioning_keyframe, for rviz's PoseArray display (conditioning/trajectory).
geometry_msgs::PoseArray viewPoseArray(const std::vector<geometry_msgs::TransformStamped>& views);

}  // namespace multimodal_nvs
