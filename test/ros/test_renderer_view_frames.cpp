// The virtual views of a burst on tf: names, parents, and poses that invert the rendered
// world-to-camera transforms. Plain gtest, no master.
#include <gtest/gtest.h>
#include <tf2_eigen/tf2_eigen.h>

#include "multimodal_nvs/ros/renderer_view_frames.hpp"

namespace mm = multimodal_nvs;

TEST(RendererViewFrames, ViewsAreChildrenOfTheKeyframeFrame) {
  mm::Trajectory trajectory;
  trajectory.cameras.resize(2);
  trajectory.cameras[1].world_to_camera(0, 3) = -0.5;  // view 1 sits 0.5 m to the right
  std_msgs::Header header;
  header.frame_id = "camera";
  header.stamp = ros::Time(3, 0);

  const auto in_camera = mm::virtualViewTransforms(trajectory, header, std::nullopt, "odom");
  ASSERT_EQ(in_camera.size(), 3u);
  EXPECT_EQ(in_camera[0].header.frame_id, "camera");
  EXPECT_EQ(in_camera[0].child_frame_id, "conditioning_keyframe");
  EXPECT_EQ(in_camera[2].header.frame_id, "conditioning_keyframe");
  EXPECT_EQ(in_camera[2].child_frame_id, "conditioning_view_001");
  EXPECT_EQ(in_camera[2].header.stamp, ros::Time(3, 0));
  EXPECT_DOUBLE_EQ(in_camera[2].transform.translation.x, 0.5);

  Eigen::Matrix4d keyframe_pose = Eigen::Matrix4d::Identity();
  keyframe_pose(2, 3) = 7.0;
  const auto in_world = mm::virtualViewTransforms(trajectory, header, keyframe_pose, "odom");
  EXPECT_EQ(in_world[0].header.frame_id, "odom");
  EXPECT_DOUBLE_EQ(in_world[0].transform.translation.z, 7.0);
  EXPECT_EQ(mm::virtualViewFrame(120), "conditioning_view_120");

  const geometry_msgs::PoseArray poses = mm::viewPoseArray(in_world);
  EXPECT_EQ(poses.header.frame_id, "conditioning_keyframe");
  ASSERT_EQ(poses.poses.size(), 2u);
  EXPECT_DOUBLE_EQ(poses.poses[1].position.x, 0.5);
}
