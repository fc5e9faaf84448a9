// The renderer nodelet's per-frame steps: which set becomes the keyframe, when the live view or
// the preset burst is rendered and published, and what a dropped set or a missing keyframe
// reports. Plain gtest, no master: tf and the publishers are stand-ins.
#include <gtest/gtest.h>

#include <algorithm>

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

/// A fresh session on a Node; step() hands it one set that arrived now.
class RendererSessionTest : public ::testing::Test {
 protected:
  mm::RendererStep step(const Set& set, const mm::ConditioningRendererSettings& s) {
    return session.onInputSet(set.image, set.depth, set.mask, set.info, s,
                              std::chrono::steady_clock::now());
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

TEST_F(RendererSessionTest, TfModeTakesTheFirstSetAsKeyframeAndRendersEverySet) {
  const auto s = settings(mm::TrajectorySource::kTf);
  const mm::RendererStep first = firstKeyframe(s);
  EXPECT_EQ(first.keyframe_points, 6u * 8u - 1u);  // every grid pixel but the NaN one
  EXPECT_TRUE(first.live_frame);
  EXPECT_GE(first.frame_ms, first.render_ms);
  EXPECT_FALSE(first.burst);
  EXPECT_TRUE(first.error.empty());

  const mm::RendererStep second = step(stampedSet(ros::Time(10, 100000000)), s);
  EXPECT_FALSE(second.keyframe);  // interval 0: the keyframe stays
  EXPECT_TRUE(second.live_frame);
  EXPECT_EQ(node.pose_lookups, (std::vector<std::string>{"map <- cam", "map <- cam"}));
  EXPECT_EQ(node.engine_requests, (std::vector<int>{1, 1}));
  // Each live frame carries its own set's header, at the render size.
  EXPECT_EQ(node.published, (std::vector<ros::Time>{ros::Time(10, 0), ros::Time(10, 100000000)}));
  EXPECT_EQ(node.published_sizes.back(), (mm::ImageSize{12, 16}));
}

TEST_F(RendererSessionTest, TfModeWithoutTransformDropsTheSetAndTakesNoKeyframe) {
  node.tf_available = false;
  const auto s = settings(mm::TrajectorySource::kTf);
  const mm::RendererStep dropped = step(stampedSet(ros::Time(10, 0)), s);
  EXPECT_EQ(dropped.fault.fault, rc::RendererFault::kTransformUnavailable);
  EXPECT_FALSE(dropped.keyframe);
  EXPECT_FALSE(dropped.live_frame);
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
  EXPECT_FALSE(first.live_frame);
  EXPECT_EQ(first.burst_frames, 3);
  EXPECT_EQ(first.report, mm::burstReport(s, first.burst_ms, ""));
  EXPECT_TRUE(first.warning.empty());  // no export
  EXPECT_EQ(node.published.size(), 3u);
  EXPECT_TRUE(node.pose_lookups.empty());  // preset mode needs no tf

  // Between keyframes a set is only checked: nothing rendered, a bad one still reported.
  const mm::RendererStep between = step(stampedSet(ros::Time(10, 500000000)), s);
  EXPECT_TRUE(between.fault.ok());
  EXPECT_FALSE(between.keyframe || between.burst || between.live_frame);
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
