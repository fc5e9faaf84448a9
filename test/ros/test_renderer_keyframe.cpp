// The renderer nodelet's keyframe policy and keyframe: when a keyframe is due, the cloud kept for
// the current parameters, and the live view. Plain gtest, no master.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "multimodal_nvs/ros/renderer_keyframe.hpp"

namespace mm = multimodal_nvs;
namespace rc = mm::ros_conversions;

namespace {

/// A keyframe input on a 16x24 grid at stride 2 of a 32x48 image, all kept at 5 m but one corner
/// region without depth.
rc::RendererInput keyframeInput(float depth_m = 5.0f) {
  rc::RendererInput in;
  in.header.stamp = ros::Time(100, 0);
  in.header.frame_id = "camera";
  in.image_size = {32, 48};
  in.grid_size = {16, 24};
  in.stride = 2;
  in.grid_intrinsics = {20.0, 20.0, 11.5, 7.5};
  in.image_intrinsics = {40.0, 40.0, 23.0, 15.0};
  in.image_bgr = cv::Mat(32, 48, CV_8UC3, cv::Scalar(50, 100, 150));
  in.grid_bgr = cv::Mat(16, 24, CV_8UC3, cv::Scalar(50, 100, 150));
  in.depth = cv::Mat(16, 24, CV_32FC1, cv::Scalar(depth_m));
  in.depth(cv::Rect(0, 0, 4, 4)).setTo(0.0f);
  in.kept = cv::Mat(16, 24, CV_8UC1, cv::Scalar(255));
  return in;
}

mm::ConditioningRendererSettings settings(mm::ImageSize render) {
  mm::ConditioningRendererSettings s;
  s.backprojection.render_size = render;
  s.backprojection.edge_threshold = 0.0f;  // a flat plane has no edge; keep the count exact
  s.backprojection.resize_to_render = true;
  return s;
}

}  // namespace

TEST(KeyframeSchedule, FirstRequestedStaleAndInterval) {
  mm::KeyframeSchedule schedule;
  EXPECT_TRUE(schedule.due(ros::Time(10, 0), 0.0));  // no keyframe yet
  schedule.taken(ros::Time(10, 0));
  EXPECT_FALSE(schedule.due(ros::Time(10, 0), 0.0));
  EXPECT_FALSE(schedule.due(ros::Time(500, 0), 0.0));       // interval 0: never by time
  EXPECT_TRUE(schedule.due(ros::Time(9, 999999999), 0.0));  // time went back: stale keyframe
  EXPECT_FALSE(schedule.due(ros::Time(11, 999999999), 2.0));
  EXPECT_TRUE(schedule.due(ros::Time(12, 0), 2.0));  // exactly the interval
  schedule.request();
  EXPECT_TRUE(schedule.due(ros::Time(10, 1), 0.0));
  EXPECT_TRUE(schedule.due(ros::Time(10, 1), 0.0));  // asking does not serve the request
  schedule.taken(ros::Time(10, 1));
  EXPECT_FALSE(schedule.due(ros::Time(10, 2), 0.0));
}

TEST(RendererKeyframe, MakeLiftsTheKeptGridAndKeepsThePreviousOnFailure) {
  std::optional<mm::RendererKeyframe> keyframe;
  // Grid 16x24 smaller than the render size: auto keeps one point per grid pixel with depth.
  const auto s = settings({32, 48});
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose(0, 3) = 1.0;
  ASSERT_TRUE(mm::RendererKeyframe::make(keyframeInput(), pose, s, keyframe).ok());
  ASSERT_TRUE(keyframe.has_value());
  EXPECT_EQ(keyframe->cloud().size(), std::size_t(16 * 24 - 16));
  EXPECT_EQ(keyframe->input().header.stamp, ros::Time(100, 0));
  EXPECT_TRUE(keyframe->cameraToWorld().isApprox(pose));

  rc::RendererInput empty = keyframeInput(0.0f);
  empty.header.stamp = ros::Time(200, 0);
  const rc::RendererStatus status =
      mm::RendererKeyframe::make(std::move(empty), Eigen::Matrix4d::Identity(), s, keyframe);
  EXPECT_EQ(status.fault, rc::RendererFault::kNoKeptPixel);
  EXPECT_NE(status.reason.find("keyframe: "), std::string::npos) << status.reason;
  EXPECT_EQ(keyframe->input().header.stamp, ros::Time(100, 0));  // the previous one stays
}

TEST(RendererKeyframe, CloudFollowsTheRenderSize) {
  std::optional<mm::RendererKeyframe> keyframe;
  ASSERT_TRUE(mm::RendererKeyframe::make(keyframeInput(), Eigen::Matrix4d::Identity(),
                                         settings({32, 48}), keyframe)
                  .ok());
  rc::RendererStatus status;
  const mm::ColoredCloud* same = keyframe->cloudFor(settings({32, 48}), status);
  ASSERT_NE(same, nullptr);
  EXPECT_TRUE(status.ok());
  EXPECT_EQ(same->size(), std::size_t(16 * 24 - 16));
  // A render size the grid covers: auto resamples the grid to it (8x12 points, 2x2 without depth).
  const mm::ColoredCloud* resized = keyframe->cloudFor(settings({8, 12}), status);
  ASSERT_NE(resized, nullptr);
  EXPECT_TRUE(status.ok());
  EXPECT_EQ(resized->size(), std::size_t(8 * 12 - 4));
  EXPECT_EQ(keyframe->cloud().size(), resized->size());
}

TEST(RendererKeyframe, LiveViewIsTheRelativePoseAtTheRenderSize) {
  std::optional<mm::RendererKeyframe> keyframe;
  Eigen::Matrix4d key_pose = Eigen::Matrix4d::Identity();
  key_pose(0, 3) = 2.0;
  ASSERT_TRUE(
      mm::RendererKeyframe::make(keyframeInput(), key_pose, settings({32, 48}), keyframe).ok());
  Eigen::Matrix4d now = key_pose;
  now(2, 3) = 0.5;  // 0.5 m forward of the keyframe
  const mm::Trajectory view = mm::liveView(*keyframe, keyframeInput(), now, {16, 24});
  ASSERT_EQ(view.cameras.size(), 1u);
  EXPECT_EQ(view.size, (mm::ImageSize{16, 24}));
  Eigen::Matrix4d expected = Eigen::Matrix4d::Identity();
  expected(2, 3) = -0.5;  // keyframe points come 0.5 m closer
  EXPECT_TRUE(view.cameras[0].world_to_camera.isApprox(expected, 1e-12));
  EXPECT_DOUBLE_EQ(view.cameras[0].intrinsics.fx, 20.0);  // image K (40) at half size
}
