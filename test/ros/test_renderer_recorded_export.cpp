// The recorded-trajectory export: the collector's stages, and the folder it writes (complete, or
// nothing at all when cancelled). That the arrays equal render_conditioning's on the same keyframe
// and poses is the VoD rostest's job (test_renderer_vod). Plain gtest, no master.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "multimodal_nvs/ros/renderer_recorded_export.hpp"
#include "multimodal_nvs/ros/renderer_session.hpp"
#include "renderer_test_sets.hpp"

namespace mm = multimodal_nvs;
namespace rc = mm::ros_conversions;
namespace fs = std::filesystem;
using Stage = mm::RecordedPoseCollector::Stage;

namespace {

Eigen::Matrix4d movedBy(double x) {
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose(0, 3) = x;
  return pose;
}

mm::RecordedExportRequest request(int poses, double duration = 0.0) {
  mm::RecordedExportRequest r;
  r.num_poses = poses;
  r.duration = duration;
  r.num_frames = 5;
  r.output_dir = "/unused";
  return r;
}

}  // namespace

TEST(RecordedPoseCollector, WaitsForAKeyframeNewerThanTheRequestThenCollectsInOrder) {
  mm::RecordedPoseCollector c;
  c.start(request(3), ros::Time(5, 0));
  EXPECT_FALSE(c.acceptsKeyframe(ros::Time(5, 0)));  // computed from an image seen before
  EXPECT_TRUE(c.acceptsKeyframe(ros::Time(6, 0)));
  c.cameraFrame(ros::Time(6, 0), movedBy(1), {});  // nothing before the keyframe
  EXPECT_EQ(c.collected(), 0);
  c.keyframe(ros::Time(6, 0), movedBy(0), {});
  EXPECT_EQ(c.stage(), Stage::kCollecting);
  c.cameraFrame(ros::Time(6, 0), movedBy(9), {});  // the keyframe's own image: already pose 0
  c.cameraFrame(ros::Time(7, 0), movedBy(1), {});
  c.cameraFrame(ros::Time(8, 0), movedBy(2), {});
  EXPECT_EQ(c.stage(), Stage::kComplete);
  c.cameraFrame(ros::Time(9, 0), movedBy(3), {});  // complete: ignored
  const mm::RecordedPoses poses = c.take();
  EXPECT_EQ(c.stage(), Stage::kIdle);
  ASSERT_EQ(poses.camera_to_world.size(), 3u);
  EXPECT_EQ(poses.camera_to_world[2](0, 3), 2.0);
}

TEST(RecordedPoseCollector, ADurationStopsAtTheFirstFrameBeyondIt) {
  mm::RecordedPoseCollector c;
  c.start(request(0, 1.5), std::nullopt);
  c.keyframe(ros::Time(1, 0), movedBy(0), {});
  c.cameraFrame(ros::Time(2, 0), movedBy(1), {});
  c.cameraFrame(ros::Time(2, 500000000), movedBy(1), {});
  EXPECT_EQ(c.stage(), Stage::kCollecting);
  c.cameraFrame(ros::Time(2, 600000000), movedBy(1), {});
  EXPECT_EQ(c.stage(), Stage::kComplete);
  EXPECT_EQ(c.collected(), 3);
}

TEST(RecordedPoseCollector, TimeGoingBackAborts) {
  mm::RecordedPoseCollector c;
  c.start(request(4), std::nullopt);
  c.keyframe(ros::Time(1, 0), movedBy(0), {});
  c.cameraFrame(ros::Time(2, 0), movedBy(1), {});
  c.cameraFrame(ros::Time(1, 500000000), movedBy(1), {});
  EXPECT_EQ(c.stage(), Stage::kAborted);
  EXPECT_NE(c.abortReason().find("went back"), std::string::npos);
  c.reset();
  EXPECT_EQ(c.stage(), Stage::kIdle);
}

TEST(RecordedExportRequest, InvalidRequestsAreNamed) {
  EXPECT_FALSE(mm::recordedExportRequestError(request(3)));
  EXPECT_TRUE(mm::recordedExportRequestError(request(0)));
  EXPECT_TRUE(mm::recordedExportRequestError(request(6)));  // more poses than frames
  auto no_dir = request(3);
  no_dir.output_dir.clear();
  EXPECT_TRUE(mm::recordedExportRequestError(no_dir));
  EXPECT_TRUE(mm::recordedExportRequestError(request(0, -1.0)));
}

namespace {

/// A job from makeSet(2)'s keyframe (a plane 2 m ahead) with three poses moving right.
class RecordedExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("mmnvs_recorded_export_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    Set set = makeSet(2);
    set.image.header.stamp = ros::Time(10, 0);
    ASSERT_TRUE(
        rc::rendererInputFromMessages(set.image, set.depth, set.mask, set.info, true, job.keyframe)
            .ok());
    job.settings.backprojection.render_size = {12, 16};
    job.settings.backprojection.edge_threshold = 0.0f;
    job.settings.resize_depth = mm::DepthResize::kNo;
    job.settings.world_frame = "odom";
    job.backprojection = mm::keyframeBackprojection(job.settings, job.keyframe.grid_size);
    job.cloud = mm::buildColoredCloud(job.keyframe.depth, job.keyframe.kept, job.keyframe.grid_bgr,
                                      job.keyframe.grid_intrinsics, job.backprojection);
    job.poses.request = request(3);
    job.poses.request.output_dir = dir.string();
    for (int j = 0; j < 3; ++j) {
      job.poses.stamps.push_back(ros::Time(10 + j, 0));
      job.poses.camera_to_world.push_back(movedBy(0.05 * j));
      job.poses.ground_truth.push_back(j == 1 ? cv::Mat() : job.keyframe.image_bgr.clone());
    }
  }
  void TearDown() override { fs::remove_all(dir); }

  fs::path dir;
  mm::RecordedExportJob job;
  mm::PointSplatter splatter{1};
};

}  // namespace

TEST_F(RecordedExportTest, WritesTheWholeFolderUnderItsFinalNameOnlyWhenComplete) {
  std::vector<int> progress;
  const mm::RecordedExportResult r = mm::exportRecordedTrajectory(
      splatter, job,
      [&](int done, int total) {
        EXPECT_EQ(total, 5);
        progress.push_back(done);
      },
      [] { return false; });
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.folder, (dir / "0000000010_000000000").string());
  EXPECT_FALSE(fs::exists(r.folder + ".partial"));
  EXPECT_EQ(progress.back(), 5);
  for (const char* file :
       {"gen3c/rendered_warp_images.npy", "gen3c/rendered_warp_masks.npy", "gen3c/input_image.png",
        "metrics.json", "keyframe/image.png", "keyframe/depth.npy", "keyframe/valid.npy",
        "keyframe/poses/002.json", "keyframe/render_conditioning.txt"}) {
    EXPECT_TRUE(fs::exists(r.folder + "/" + file)) << file;
  }
  // The poses round-trip exactly through VoD's pose format.
  EXPECT_EQ(mm::io::readVodPose(r.folder + "/keyframe/poses/002.json", "odomToCamera"),
            job.poses.camera_to_world[2]);
  // metrics.json: the two poses with a live image (frames 0 and 4), frame 2 had none.
  std::ifstream in(r.folder + "/metrics.json");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("\"frame\": 0,"), std::string::npos);
  EXPECT_EQ(text.str().find("\"frame\": 2,"), std::string::npos);
  EXPECT_NE(text.str().find("\"frame\": 4,"), std::string::npos);
  ASSERT_EQ(r.trajectory.recorded_frames, (std::vector<int>{0, 2, 4}));
}

TEST_F(RecordedExportTest, ACancelLeavesNoFolder) {
  const mm::RecordedExportResult r = mm::exportRecordedTrajectory(
      splatter, job, [](int, int) {}, [] { return true; });
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.cancelled);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST_F(RecordedExportTest, AnUnwritableFolderFailsWithTheReason) {
  fs::create_directories(dir);
  std::ofstream(dir / "blocker") << "x";
  job.poses.request.output_dir = (dir / "blocker").string();
  const mm::RecordedExportResult r = mm::exportRecordedTrajectory(
      splatter, job, [](int, int) {}, [] { return false; });
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.cancelled);
  EXPECT_NE(r.error.find("recorded export failed"), std::string::npos);
}
