#include "multimodal_nvs/ros/renderer_view_frames.hpp"

#include <tf2_eigen/tf2_eigen.h>

#include <Eigen/Geometry>
#include <cstdio>

namespace multimodal_nvs {

std::string virtualViewFrame(int index) {
  char name[40];
  std::snprintf(name, sizeof name, "conditioning_view_%03d", index);
  return name;
}

namespace {

geometry_msgs::TransformStamped transform(const std::string& parent, const std::string& child,
                                          const ros::Time& stamp, const Eigen::Matrix4d& pose) {
  Eigen::Isometry3d isometry = Eigen::Isometry3d::Identity();
  isometry.linear() = pose.block<3, 3>(0, 0);
  isometry.translation() = pose.block<3, 1>(0, 3);
  geometry_msgs::TransformStamped msg = tf2::eigenToTransform(isometry);
  msg.header.frame_id = parent;
  msg.header.stamp = stamp;
  msg.child_frame_id = child;
  return msg;
}

}  // namespace

std::vector<geometry_msgs::TransformStamped> virtualViewTransforms(
    const Trajectory& trajectory, const std_msgs::Header& keyframe_header,
    const std::optional<Eigen::Matrix4d>& keyframe_in_world, const std::string& world_frame) {
  std::vector<geometry_msgs::TransformStamped> out;
  out.push_back(keyframe_in_world ? transform(world_frame, kKeyframeViewFrame,
                                              keyframe_header.stamp, *keyframe_in_world)
                                  : transform(keyframe_header.frame_id, kKeyframeViewFrame,
                                              keyframe_header.stamp, Eigen::Matrix4d::Identity()));
  for (std::size_t i = 0; i < trajectory.cameras.size(); ++i) {
    // world_to_camera maps the keyframe camera's frame into view i: view i's pose is its inverse.
    const Eigen::Matrix4d pose = trajectory.cameras[i].world_to_camera.inverse();
    out.push_back(transform(kKeyframeViewFrame, virtualViewFrame(static_cast<int>(i)),
                            keyframe_header.stamp, pose));
  }
  return out;
}

geometry_msgs::PoseArray viewPoseArray(const std::vector<geometry_msgs::TransformStamped>& views) {
  geometry_msgs::PoseArray out;
  out.header.frame_id = kKeyframeViewFrame;
  if (!views.empty()) out.header.stamp = views.front().header.stamp;
  for (std::size_t i = 1; i < views.size(); ++i) {
    geometry_msgs::Pose pose;
    pose.position.x = views[i].transform.translation.x;
    pose.position.y = views[i].transform.translation.y;
    pose.position.z = views[i].transform.translation.z;
    pose.orientation = views[i].transform.rotation;
    out.poses.push_back(pose);
  }
  return out;
}

}  // namespace multimodal_nvs
