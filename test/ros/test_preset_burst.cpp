// The renderer nodelet's preset burst: frames published in order with their stamps, the GEN3C
// folder per keyframe, the report. Plain gtest, no master.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "multimodal_nvs/ros/preset_burst.hpp"

namespace mm = multimodal_nvs;
namespace rc = mm::ros_conversions;
namespace fs = std::filesystem;

namespace {

rc::RendererInput keyframeInput() {
  rc::RendererInput in;
  in.header.stamp = ros::Time(1700000000, 5);
  in.header.frame_id = "camera";
  in.image_size = in.grid_size = {16, 24};
  in.grid_intrinsics = in.image_intrinsics = {20.0, 20.0, 11.5, 7.5};
  in.image_bgr = cv::Mat(16, 24, CV_8UC3);
  cv::RNG(2).fill(in.image_bgr, cv::RNG::UNIFORM, 0, 256);
  in.grid_bgr = in.image_bgr;
  in.depth = cv::Mat(16, 24, CV_32FC1, cv::Scalar(6.0f));
  in.kept = cv::Mat(16, 24, CV_8UC1, cv::Scalar(255));
  return in;
}

mm::ConditioningRendererSettings burstSettings() {
  mm::ConditioningRendererSettings s;
  s.source = mm::TrajectorySource::kPreset;
  s.preset = mm::TrajectoryPreset::kLeft;
  s.magnitude = 0.5;
  s.num_frames = 5;
  s.burst_frame_rate = 10.0;
  s.backprojection.render_size = {16, 24};
  s.threads = 1;
  return s;
}

struct Published {
  int count = 0;
  std::vector<ros::Time> stamps;
  std::vector<double> first_column_x;  ///< w2c translation x, per frame: the trajectory order
};

}  // namespace

TEST(PresetBurst, StampsFolderNamesAndReport) {
  EXPECT_EQ(mm::burstFrameStamp(ros::Time(10, 0), 0, 24.0), ros::Time(10, 0));
  EXPECT_EQ(mm::burstFrameStamp(ros::Time(10, 0), 12, 24.0), ros::Time(10, 500000000));
  EXPECT_EQ(mm::gen3cExportFolder("/x", ros::Time(12, 345)), "/x/0000000012_000000345");
  auto s = burstSettings();
  EXPECT_EQ(mm::burstReport(s, 12.4, ""),
            "rendered 5 frames at 16x24 (left 0.5 m, gen3c) in 12 ms");
  EXPECT_EQ(mm::burstReport(s, 12.6, "/x/f"),
            "rendered 5 frames at 16x24 (left 0.5 m, gen3c) in 13 ms; GEN3C folder /x/f");
  EXPECT_NE(mm::burstUnavailableReason(false).find("no keyframe yet"), std::string::npos);
  EXPECT_EQ(mm::burstUnavailableReason(true), "the keyframe has no point to render");
}

TEST(PresetBurst, ExportWantedOnlyForAnExportedPreset) {
  auto s = burstSettings();
  EXPECT_FALSE(mm::presetExportWanted(s));
  s.export_dir = "/tmp/x";
  EXPECT_TRUE(mm::presetExportWanted(s));
  s.source = mm::TrajectorySource::kTf;
  EXPECT_FALSE(mm::presetExportWanted(s));
}

TEST(PresetBurst, PublishesEveryFrameInOrderAndExportsOneFolder) {
  const auto settings = burstSettings();
  std::optional<mm::RendererKeyframe> keyframe;
  ASSERT_TRUE(
      mm::RendererKeyframe::make(keyframeInput(), Eigen::Matrix4d::Identity(), settings, keyframe)
          .ok());
  mm::PointSplatter splatter(1);
  auto exported = settings;
  exported.export_dir = "/tmp/mmnvs_test_preset_burst_" + std::to_string(::getpid());
  fs::remove_all(exported.export_dir);
  for (const auto& s : {settings, exported}) {
    Published out;
    std::vector<std::string> warnings;
    const mm::PresetBurstResult result = mm::renderPresetBurst(
        splatter, *keyframe, keyframe->cloud(), s,
        [&](const mm::RenderedFrame& frame, const mm::TargetCamera& camera,
            const std_msgs::Header& header) {
          ++out.count;
          EXPECT_EQ(frame.bgr.size(), cv::Size(24, 16));
          EXPECT_EQ(header.frame_id, "camera");
          out.stamps.push_back(header.stamp);
          out.first_column_x.push_back(camera.world_to_camera(0, 3));
        },
        [&](const std::string& w) { warnings.push_back(w); });
    ASSERT_TRUE(result.ok) << result.error;
    const std::string& folder = result.gen3c_folder;
    ASSERT_EQ(out.count, 5);
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(out.stamps[std::size_t(i)], ros::Time(1700000000, 5) + ros::Duration(i / 10.0));
    }
    // A left preset moves the camera left monotonically: w2c x grows frame by frame.
    EXPECT_DOUBLE_EQ(out.first_column_x.front(), 0.0);
    for (int i = 1; i < 5; ++i)
      EXPECT_GT(out.first_column_x[std::size_t(i)], out.first_column_x[std::size_t(i - 1)]);
    if (s.export_dir.empty()) {
      EXPECT_TRUE(folder.empty());
      EXPECT_TRUE(warnings.empty());
    } else {
      EXPECT_EQ(folder, exported.export_dir + "/1700000000_000000005");
      EXPECT_TRUE(fs::exists(folder + "/rendered_warp_images.npy"));
      EXPECT_FALSE(fs::exists(folder + ".partial"));
      ASSERT_EQ(warnings.size(), 1u);  // 5 frames at 16x24 is not GEN3C's size
      EXPECT_NE(warnings[0].find("5 frames at 16x24"), std::string::npos) << warnings[0];
    }
  }
  fs::remove_all(exported.export_dir);
}

TEST(PresetBurst, FailuresAreReportedNotThrown) {
  auto settings = burstSettings();
  std::optional<mm::RendererKeyframe> keyframe;
  ASSERT_TRUE(
      mm::RendererKeyframe::make(keyframeInput(), Eigen::Matrix4d::Identity(), settings, keyframe)
          .ok());
  mm::PointSplatter splatter(1);
  int published = 0;
  const auto count = [&](const mm::RenderedFrame&, const mm::TargetCamera&,
                         const std_msgs::Header&) { ++published; };
  const auto ignore = [](const std::string&) {};
  // Zooming in by more than the field of view: no trajectory, nothing published.
  settings.preset = mm::TrajectoryPreset::kZoomIn;
  settings.magnitude = 179.0;
  mm::PresetBurstResult result =
      mm::renderPresetBurst(splatter, *keyframe, keyframe->cloud(), settings, count, ignore);
  EXPECT_FALSE(result.ok);
  EXPECT_EQ(result.error.rfind("preset burst failed: ", 0), 0u) << result.error;
  EXPECT_EQ(published, 0);
  // An export directory that cannot be created.
  settings = burstSettings();
  settings.export_dir = "/proc/mmnvs_no_such_dir";
  result = mm::renderPresetBurst(splatter, *keyframe, keyframe->cloud(), settings, count, ignore);
  EXPECT_FALSE(result.ok);
  EXPECT_FALSE(result.error.empty());
  EXPECT_TRUE(result.gen3c_folder.empty());
  EXPECT_EQ(published, 0);
}
