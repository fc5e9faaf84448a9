// The renderer nodelet's per-frame steps: which set becomes the keyframe, when the live view (per
// camera image) or the preset burst is rendered and published, what a dropped set, a missing tf or
// a missing keyframe reports, and how the recorded-trajectory export collects its poses. Plain
// gtest, no master: tf and the publishers are stand-ins.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "multimodal_nvs/ros/preset_burst.hpp"
#include "multimodal_nvs/ros/renderer_session.hpp"
#include "renderer_test_sets.hpp"

namespace mm = multimodal_nvs;
namespace rc = mm::ros_conversions;

namespace {

/// makeSet(2) (12x16 image, depth on its 6x8 grid) stamped `stamp`; `with_depth` false leaves it
/// without any depth.
Set stampedSet(ros::Time stamp, bool with_depth = true) {
  Set set = makeSet(2);
  set.image.header.stamp = stamp;
  if (!with_depth) std::fill(set.depth.data.begin(), set.depth.data.end(), 0);
  return set;
}

/// A step that took a new keyframe stamped `stamp`.
void expectNewKeyframe(const mm::RendererStep& step, ros::Time stamp) {
  EXPECT_TRUE(step.fault.ok()) << step.fault.reason;
  EXPECT_TRUE(step.keyframe);
  EXPECT_EQ(step.keyframe_stamp, stamp);
}

mm::ConditioningRendererSettings settings(mm::TrajectorySource source) {
  mm::ConditioningRendererSettings s;
  s.source = source;
  s.world_frame = "map";
  s.preset = mm::TrajectoryPreset::kLeft;
  s.magnitude = 0.2;
  s.num_frames = 3;
  s.backprojection.render_size = {12, 16};
  s.backprojection.edge_threshold = 0.0f;  // a flat plane has no edge
  s.resize_depth = mm::DepthResize::kNo;   // one point per grid pixel
  s.threads = 1;
  return s;
}

/// tf, the engine and the publishers, recording what the session asked of them.
struct Node {
  bool tf_available = true;
  std::vector<std::string> pose_lookups;  ///< "world <- frame" per lookup
  std::vector<int> engine_requests;       ///< thread counts asked for
  std::set<ros::Time> missing_tf;         ///< stamps without a transform
  std::vector<ros::Time> published;
  std::vector<mm::ImageSize> published_sizes;
  std::vector<std::size_t> views_published;  ///< views per burst on tf
  mm::PointSplatter splatter{1};

  mm::RendererSession session() {
    return mm::RendererSession(mm::RendererSessionIo{
        [this](const std::string& world, const std_msgs::Header& header, Eigen::Matrix4d& pose) {
          pose_lookups.push_back(world + " <- " + header.frame_id);
          if (!tf_available || missing_tf.count(header.stamp)) {
            return rc::RendererStatus::failure(rc::RendererFault::kTransformUnavailable, "no tf");
          }
          pose = Eigen::Matrix4d::Identity();
          pose(0, 3) = 0.1 * static_cast<double>(pose_lookups.size());
          return rc::RendererStatus::success();
        },
        [this](int threads) -> mm::PointSplatter& {
          engine_requests.push_back(threads);
          return splatter;
        },
        [this](const mm::RenderedFrame&, const mm::PinholeIntrinsics&, const mm::ImageSize& size,
               const std_msgs::Header& header) {
          published.push_back(header.stamp);
          published_sizes.push_back(size);
        },
        [this](const mm::Trajectory& views, const std_msgs::Header&) {
          views_published.push_back(views.cameras.size());
        }});
  }
};

/// A fresh session on a Node; step() hands it one set that arrived now.
class RendererSessionTest : public ::testing::Test {
 protected:
  mm::RendererStep step(const Set& set, const mm::ConditioningRendererSettings& s) {
    return session.onInputSet(set.image, set.depth, set.mask, set.info, s,
                              std::chrono::steady_clock::now());
  }
  /// One camera image (the set's image) stamped `stamp` that arrived now.
  mm::RendererStep camera(ros::Time stamp, const mm::ConditioningRendererSettings& s,
                          bool render_live = true) {
    return session.onCameraImage(stampedSet(stamp).image, s, std::chrono::steady_clock::now(),
                                 render_live);
  }
  /// The first set, stamped 10 s: always the keyframe.
  mm::RendererStep firstKeyframe(const mm::ConditioningRendererSettings& s) {
    const mm::RendererStep first = step(stampedSet(ros::Time(10, 0)), s);
    expectNewKeyframe(first, ros::Time(10, 0));
    return first;
  }

  Node node;
  mm::RendererSession session = node.session();
};

}  // namespace

TEST_F(RendererSessionTest, TfModeRendersEveryCameraImageFromTheKeyframe) {
  const auto s = settings(mm::TrajectorySource::kTf);
  // The camera is faster than the depth nodelet: two images arrive before their keyframe.
  EXPECT_TRUE(camera(ros::Time(10, 0), s).live_frames.empty());
  EXPECT_TRUE(camera(ros::Time(10, 100000000), s).live_frames.empty());
  EXPECT_TRUE(node.published.empty());
  const mm::RendererStep first = firstKeyframe(s);
  EXPECT_EQ(first.keyframe_points, 6u * 8u - 1u);  // every grid pixel but the NaN one
  ASSERT_EQ(first.live_frames.size(), 2u);         // both waiting images, in order
  EXPECT_GE(first.live_frames[0].frame_ms, first.live_frames[0].render_ms);
  EXPECT_FALSE(first.burst);
  EXPECT_TRUE(first.error.empty());

  // Camera images without a depth set are rendered from the keyframe as they come.
  const mm::RendererStep next = camera(ros::Time(10, 200000000), s);
  EXPECT_EQ(next.live_frames.size(), 1u);
  // A depth set that is no keyframe (interval 0) renders nothing by itself.
  const mm::RendererStep set = step(stampedSet(ros::Time(10, 200000000)), s);
  EXPECT_FALSE(set.keyframe);
  EXPECT_TRUE(set.live_frames.empty());
  // Each live frame carries its camera image's header, at the render size.
  EXPECT_EQ(node.published, (std::vector<ros::Time>{ros::Time(10, 0), ros::Time(10, 100000000),
                                                    ros::Time(10, 200000000)}));
  EXPECT_EQ(node.published_sizes.back(), (mm::ImageSize{12, 16}));
  EXPECT_TRUE(node.views_published.empty());  // live frames are real camera poses
}

TEST_F(RendererSessionTest, TfModeMissingTransformDropsThatCameraImageOnly) {
  const auto s = settings(mm::TrajectorySource::kTf);
  firstKeyframe(s);
  node.missing_tf.insert(ros::Time(10, 100000000));
  const mm::RendererStep dropped = camera(ros::Time(10, 100000000), s);
  EXPECT_EQ(dropped.fault.fault, rc::RendererFault::kTransformUnavailable);
  EXPECT_TRUE(dropped.live_frames.empty());
  EXPECT_EQ(camera(ros::Time(10, 200000000), s).live_frames.size(), 1u);
  EXPECT_EQ(node.published, (std::vector<ros::Time>{ros::Time(10, 200000000)}));
}

TEST_F(RendererSessionTest, CameraImagesOlderThanTheKeyframeWaitForTheNextOne) {
  const auto s = settings(mm::TrajectorySource::kTf);
  firstKeyframe(s);
  EXPECT_EQ(camera(ros::Time(10, 0), s).live_frames.size(), 1u);
  // A bag loop: the camera goes back in time; the keyframe (from the future) is not used.
  EXPECT_TRUE(camera(ros::Time(5, 0), s).live_frames.empty());
  const mm::RendererStep looped = step(stampedSet(ros::Time(5, 0)), s);
  expectNewKeyframe(looped, ros::Time(5, 0));
  EXPECT_EQ(looped.live_frames.size(), 1u);
  EXPECT_EQ(node.published.back(), ros::Time(5, 0));
}

TEST_F(RendererSessionTest, TfModeWithoutTransformDropsTheSetAndTakesNoKeyframe) {
  node.tf_available = false;
  const auto s = settings(mm::TrajectorySource::kTf);
  const mm::RendererStep dropped = step(stampedSet(ros::Time(10, 0)), s);
  EXPECT_EQ(dropped.fault.fault, rc::RendererFault::kTransformUnavailable);
  EXPECT_FALSE(dropped.keyframe);
  EXPECT_TRUE(dropped.live_frames.empty());
  EXPECT_TRUE(node.published.empty());
  EXPECT_TRUE(node.engine_requests.empty());
  // The keyframe is still due: the next set with a transform becomes it.
  node.tf_available = true;
  const mm::RendererStep next = step(stampedSet(ros::Time(11, 0)), s);
  expectNewKeyframe(next, ros::Time(11, 0));
}

TEST_F(RendererSessionTest, PresetModeRendersTheBurstOnANewKeyframeOnly) {
  const auto s = settings(mm::TrajectorySource::kPreset);
  const mm::RendererStep first = firstKeyframe(s);
  EXPECT_TRUE(first.burst) << first.error;
  EXPECT_TRUE(first.live_frames.empty());
  EXPECT_EQ(first.burst_frames, 3);
  EXPECT_EQ(node.views_published, (std::vector<std::size_t>{3}));
  EXPECT_EQ(first.report, mm::burstReport(s, first.burst_ms, ""));
  EXPECT_TRUE(first.warning.empty());  // no export
  EXPECT_EQ(node.published.size(), 3u);
  EXPECT_TRUE(node.pose_lookups.empty());  // preset mode needs no tf

  // Between keyframes a set is only checked: nothing rendered, a bad one still reported.
  const mm::RendererStep between = step(stampedSet(ros::Time(10, 500000000)), s);
  EXPECT_TRUE(between.fault.ok());
  EXPECT_FALSE(between.keyframe || between.burst || !between.live_frames.empty());
  EXPECT_TRUE(camera(ros::Time(10, 500000000), s).live_frames.empty());  // no live view
  Set bad = stampedSet(ros::Time(10, 600000000));
  bad.image.height = 40;  // the depth grid is no stride grid of it any more
  bad.image.data.resize(40 * 16 * 3);
  EXPECT_EQ(step(bad, s).fault.fault, rc::RendererFault::kGridSize);
  EXPECT_EQ(node.published.size(), 3u);
  EXPECT_EQ(node.engine_requests.size(), 1u);

  // ~set_keyframe: the next set is the keyframe and its burst follows.
  session.requestKeyframe();
  const mm::RendererStep requested = step(stampedSet(ros::Time(11, 0)), s);
  expectNewKeyframe(requested, ros::Time(11, 0));
  EXPECT_TRUE(requested.burst);
  EXPECT_EQ(node.published.size(), 6u);
  EXPECT_EQ(node.published[3], ros::Time(11, 0));  // stamped from the new keyframe
}

TEST_F(RendererSessionTest, BurstNeedsAKeyframeWithPoints) {
  const auto s = settings(mm::TrajectorySource::kPreset);
  const mm::RendererStep none = session.renderBurst(s);
  EXPECT_FALSE(none.burst);
  EXPECT_EQ(none.error, mm::burstUnavailableReason(false));
  EXPECT_TRUE(none.fault.ok());
  EXPECT_TRUE(node.engine_requests.empty());

  // A set without depth is no keyframe: dropped, and ~render still has none.
  const mm::RendererStep empty = step(stampedSet(ros::Time(10, 0), false), s);
  EXPECT_EQ(empty.fault.fault, rc::RendererFault::kNoKeptPixel);
  EXPECT_FALSE(empty.keyframe);
  EXPECT_EQ(session.renderBurst(s).error, mm::burstUnavailableReason(false));

  ASSERT_TRUE(step(stampedSet(ros::Time(11, 0)), s).burst);
  const mm::RendererStep again = session.renderBurst(s);
  EXPECT_TRUE(again.burst) << again.error;
  EXPECT_EQ(node.published.size(), 6u);
}

TEST_F(RendererSessionTest, ExportCollectsTheCameraPosesAfterANewKeyframe) {
  const auto s = settings(mm::TrajectorySource::kTf);
  using Stage = mm::RecordedPoseCollector::Stage;
  firstKeyframe(s);
  camera(ros::Time(10, 0), s);
  mm::RecordedExportRequest request;
  request.num_poses = 3;
  request.num_frames = 5;
  request.output_dir = "/unused";
  ASSERT_FALSE(session.startExport(request));
  EXPECT_EQ(session.exportCollector().stage(), Stage::kWaitingForKeyframe);
  // The next set is due (the export asked for a keyframe); its image arrived first.
  camera(ros::Time(11, 0), s);
  expectNewKeyframe(step(stampedSet(ros::Time(11, 0)), s), ros::Time(11, 0));
  EXPECT_EQ(session.exportCollector().stage(), Stage::kCollecting);
  EXPECT_EQ(session.exportCollector().collected(), 1);
  mm::RecordedExportJob job;
  EXPECT_FALSE(session.takeExportJob(s, job));
  camera(ros::Time(11, 100000000), s);
  camera(ros::Time(11, 200000000), s);
  EXPECT_EQ(session.exportCollector().stage(), Stage::kComplete);
  ASSERT_TRUE(session.takeExportJob(s, job));
  EXPECT_EQ(session.exportCollector().stage(), Stage::kIdle);
  EXPECT_EQ(job.poses.stamps, (std::vector<ros::Time>{ros::Time(11, 0), ros::Time(11, 100000000),
                                                      ros::Time(11, 200000000)}));
  ASSERT_EQ(job.poses.ground_truth.size(), 3u);
  for (const cv::Mat& gt : job.poses.ground_truth)
    EXPECT_EQ(gt.size(), cv::Size(16, 12));
  EXPECT_EQ(job.keyframe.header.stamp, ros::Time(11, 0));
  EXPECT_EQ(job.cloud.size(), 6u * 8u - 1u);
}

TEST_F(RendererSessionTest, ABehindLiveViewSkipsToTheNewestImageButTheExportKeepsEveryPose) {
  const auto s = settings(mm::TrajectorySource::kTf);
  firstKeyframe(s);
  // Three images waited while the renderer was busy: the two older ones are skipped (no render,
  // no tf lookup), the newest is rendered.
  const std::size_t lookups = node.pose_lookups.size();
  const mm::RendererStep old1 = camera(ros::Time(10, 100000000), s, false);
  const mm::RendererStep old2 = camera(ros::Time(10, 200000000), s, false);
  EXPECT_EQ(old1.live_skipped, 1);
  EXPECT_EQ(old2.live_skipped, 1);
  EXPECT_TRUE(old1.live_frames.empty() && old2.live_frames.empty());
  EXPECT_EQ(node.pose_lookups.size(), lookups);
  const mm::RendererStep newest = camera(ros::Time(10, 300000000), s, true);
  EXPECT_EQ(newest.live_skipped, 0);
  EXPECT_EQ(newest.live_frames.size(), 1u);
  EXPECT_EQ(node.published, (std::vector<ros::Time>{ros::Time(10, 300000000)}));

  // While an export collects, a skipped image still gives its pose.
  mm::RecordedExportRequest request;
  request.num_poses = 3;
  request.num_frames = 5;
  request.output_dir = "/unused";
  ASSERT_FALSE(session.startExport(request));
  expectNewKeyframe(step(stampedSet(ros::Time(11, 0)), s), ros::Time(11, 0));
  EXPECT_EQ(session.exportCollector().collected(), 1);
  EXPECT_EQ(camera(ros::Time(11, 100000000), s, false).live_skipped, 1);
  EXPECT_EQ(session.exportCollector().collected(), 2);
  camera(ros::Time(11, 200000000), s, true);
  EXPECT_EQ(session.exportCollector().stage(), mm::RecordedPoseCollector::Stage::kComplete);
}

TEST_F(RendererSessionTest, ExportAbortsOnABagLoopOrAMissingTransform) {
  const auto s = settings(mm::TrajectorySource::kTf);
  using Stage = mm::RecordedPoseCollector::Stage;
  mm::RecordedExportRequest request;
  request.output_dir = "/unused";
  ASSERT_FALSE(session.startExport(request));
  firstKeyframe(s);
  camera(ros::Time(10, 100000000), s);
  EXPECT_EQ(session.exportCollector().collected(), 2);
  camera(ros::Time(9, 0), s);  // the bag looped
  EXPECT_EQ(session.exportCollector().stage(), Stage::kAborted);
  EXPECT_NE(session.exportCollector().abortReason().find("bag loop"), std::string::npos);
  session.resetExport();

  ASSERT_FALSE(session.startExport(request));
  expectNewKeyframe(step(stampedSet(ros::Time(20, 0)), s), ros::Time(20, 0));
  node.missing_tf.insert(ros::Time(20, 100000000));
  EXPECT_EQ(camera(ros::Time(20, 100000000), s).fault.fault,
            rc::RendererFault::kTransformUnavailable);
  EXPECT_EQ(session.exportCollector().stage(), Stage::kAborted);
  EXPECT_NE(session.exportCollector().abortReason().find("no camera pose"), std::string::npos);
}

TEST_F(RendererSessionTest, ExportNeedsAnOutputDirectory) {
  mm::RecordedExportRequest request;
  EXPECT_TRUE(session.startExport(request));
  EXPECT_EQ(session.exportCollector().stage(), mm::RecordedPoseCollector::Stage::kIdle);
}
