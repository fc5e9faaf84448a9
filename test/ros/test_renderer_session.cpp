// The renderer nodelet's per-frame steps: which set becomes the keyframe, when the live view or
// the preset burst is rendered and published, and what a dropped set or a missing keyframe
// reports. Plain gtest, no master: tf and the publishers are stand-ins.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>

#include <cstring>

#include "multimodal_nvs/ros/preset_burst.hpp"
#include "multimodal_nvs/ros/renderer_session.hpp"

namespace mm = multimodal_nvs;
namespace rc = mm::ros_conversions;
namespace enc = sensor_msgs::image_encodings;

namespace {

struct Set {
  sensor_msgs::Image image, depth, mask;
  sensor_msgs::CameraInfo info;
};

/// A 16x24 bgr8 image with depth `depth_m` everywhere on its stride-2 grid (8x12), all kept.
Set makeSet(ros::Time stamp, float depth_m = 5.0f) {
  Set set;
  set.image.header.stamp = stamp;
  set.image.header.frame_id = "camera";
  set.image.height = 16;
  set.image.width = 24;
  set.image.encoding = enc::BGR8;
  set.image.step = 24 * 3;
  set.image.data.assign(16 * 24 * 3, 120);
  const int gh = 8, gw = 12;
  set.depth.height = set.mask.height = set.info.height = gh;
  set.depth.width = set.mask.width = set.info.width = gw;
  set.depth.encoding = enc::TYPE_32FC1;
  set.depth.step = gw * 4;
  set.depth.data.resize(gh * gw * 4);
  for (int i = 0; i < gh * gw; ++i)
    std::memcpy(&set.depth.data[i * 4], &depth_m, 4);
  set.mask.encoding = enc::MONO8;
  set.mask.step = gw;
  set.mask.data.assign(gh * gw, 255);
  set.info.K = {10.0, 0, 6.0, 0, 10.0, 4.0, 0, 0, 1};
  return set;
}

mm::ConditioningRendererSettings settings(mm::TrajectorySource source) {
  mm::ConditioningRendererSettings s;
  s.source = source;
  s.world_frame = "map";
  s.preset = mm::TrajectoryPreset::kLeft;
  s.magnitude = 0.2;
  s.num_frames = 3;
  s.backprojection.render_size = {16, 24};
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
  std::vector<ros::Time> published;
  std::vector<mm::ImageSize> published_sizes;
  mm::PointSplatter splatter{1};

  mm::RendererSession session() {
    return mm::RendererSession(mm::RendererSessionIo{
        [this](const std::string& world, const std_msgs::Header& header, Eigen::Matrix4d& pose) {
          pose_lookups.push_back(world + " <- " + header.frame_id);
          if (!tf_available) {
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
        }});
  }
};

mm::RendererStep step(mm::RendererSession& session, const Set& set,
                      const mm::ConditioningRendererSettings& s) {
  return session.onInputSet(set.image, set.depth, set.mask, set.info, s,
                            std::chrono::steady_clock::now());
}

}  // namespace

TEST(RendererSession, TfModeTakesTheFirstSetAsKeyframeAndRendersEverySet) {
  Node node;
  mm::RendererSession session = node.session();
  const auto s = settings(mm::TrajectorySource::kTf);
  const mm::RendererStep first = step(session, makeSet(ros::Time(10, 0)), s);
  EXPECT_TRUE(first.fault.ok()) << first.fault.reason;
  EXPECT_TRUE(first.keyframe);
  EXPECT_EQ(first.keyframe_stamp, ros::Time(10, 0));
  EXPECT_EQ(first.keyframe_points, 8u * 12u);
  EXPECT_TRUE(first.live_frame);
  EXPECT_GE(first.frame_ms, first.render_ms);
  EXPECT_FALSE(first.burst);
  EXPECT_TRUE(first.error.empty());

  const mm::RendererStep second = step(session, makeSet(ros::Time(10, 100000000)), s);
  EXPECT_FALSE(second.keyframe);  // interval 0: the keyframe stays
  EXPECT_TRUE(second.live_frame);
  EXPECT_EQ(node.pose_lookups, (std::vector<std::string>{"map <- camera", "map <- camera"}));
  EXPECT_EQ(node.engine_requests, (std::vector<int>{1, 1}));
  // Each live frame carries its own set's header, at the render size.
  EXPECT_EQ(node.published, (std::vector<ros::Time>{ros::Time(10, 0), ros::Time(10, 100000000)}));
  EXPECT_EQ(node.published_sizes.back(), (mm::ImageSize{16, 24}));
}

TEST(RendererSession, TfModeWithoutTransformDropsTheSetAndTakesNoKeyframe) {
  Node node;
  node.tf_available = false;
  mm::RendererSession session = node.session();
  const auto s = settings(mm::TrajectorySource::kTf);
  const mm::RendererStep dropped = step(session, makeSet(ros::Time(10, 0)), s);
  EXPECT_EQ(dropped.fault.fault, rc::RendererFault::kTransformUnavailable);
  EXPECT_FALSE(dropped.keyframe);
  EXPECT_FALSE(dropped.live_frame);
  EXPECT_TRUE(node.published.empty());
  EXPECT_TRUE(node.engine_requests.empty());
  // The keyframe is still due: the next set with a transform becomes it.
  node.tf_available = true;
  const mm::RendererStep next = step(session, makeSet(ros::Time(11, 0)), s);
  EXPECT_TRUE(next.keyframe);
  EXPECT_EQ(next.keyframe_stamp, ros::Time(11, 0));
}

TEST(RendererSession, PresetModeRendersTheBurstOnANewKeyframeOnly) {
  Node node;
  mm::RendererSession session = node.session();
  const auto s = settings(mm::TrajectorySource::kPreset);
  const mm::RendererStep first = step(session, makeSet(ros::Time(10, 0)), s);
  EXPECT_TRUE(first.fault.ok()) << first.fault.reason;
  EXPECT_TRUE(first.keyframe);
  EXPECT_TRUE(first.burst) << first.error;
  EXPECT_FALSE(first.live_frame);
  EXPECT_EQ(first.burst_frames, 3);
  EXPECT_EQ(first.report, mm::burstReport(s, first.burst_ms, ""));
  EXPECT_TRUE(first.warning.empty());  // no export
  EXPECT_EQ(node.published.size(), 3u);
  EXPECT_TRUE(node.pose_lookups.empty());  // preset mode needs no tf

  // Between keyframes a set is only checked: nothing rendered, a bad one still reported.
  const mm::RendererStep between = step(session, makeSet(ros::Time(10, 500000000)), s);
  EXPECT_TRUE(between.fault.ok());
  EXPECT_FALSE(between.keyframe || between.burst || between.live_frame);
  Set bad = makeSet(ros::Time(10, 600000000));
  bad.image.height = 40;  // the depth grid is no stride grid of it any more
  bad.image.data.resize(40 * 24 * 3);
  EXPECT_EQ(step(session, bad, s).fault.fault, rc::RendererFault::kGridSize);
  EXPECT_EQ(node.published.size(), 3u);
  EXPECT_EQ(node.engine_requests.size(), 1u);

  // ~set_keyframe: the next set is the keyframe and its burst follows.
  session.requestKeyframe();
  const mm::RendererStep requested = step(session, makeSet(ros::Time(11, 0)), s);
  EXPECT_TRUE(requested.keyframe);
  EXPECT_TRUE(requested.burst);
  EXPECT_EQ(node.published.size(), 6u);
  EXPECT_EQ(node.published[3], ros::Time(11, 0));  // stamped from the new keyframe
}

TEST(RendererSession, BurstNeedsAKeyframeWithPoints) {
  Node node;
  mm::RendererSession session = node.session();
  const auto s = settings(mm::TrajectorySource::kPreset);
  const mm::RendererStep none = session.renderBurst(s);
  EXPECT_FALSE(none.burst);
  EXPECT_EQ(none.error, mm::burstUnavailableReason(false));
  EXPECT_TRUE(none.fault.ok());
  EXPECT_TRUE(node.engine_requests.empty());

  // A set without depth is no keyframe: dropped, and ~render still has none.
  const mm::RendererStep empty = step(session, makeSet(ros::Time(10, 0), 0.0f), s);
  EXPECT_EQ(empty.fault.fault, rc::RendererFault::kNoKeptPixel);
  EXPECT_FALSE(empty.keyframe);
  EXPECT_EQ(session.renderBurst(s).error, mm::burstUnavailableReason(false));

  ASSERT_TRUE(step(session, makeSet(ros::Time(11, 0)), s).burst);
  const mm::RendererStep again = session.renderBurst(s);
  EXPECT_TRUE(again.burst) << again.error;
  EXPECT_EQ(node.published.size(), 6u);
}
