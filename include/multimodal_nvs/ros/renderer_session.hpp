#pragma once
// The conditioning renderer's per-frame steps: an input set checked, taken as the keyframe when due
// and rendered as the live view (tf mode) or, on a new keyframe, as the preset burst; ~render's
// burst. The node counts and logs what each step reports.
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

#include <Eigen/Core>
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"
#include "multimodal_nvs/ros/renderer_keyframe.hpp"

namespace multimodal_nvs {

/// What the node lends the steps: tf, its engine and its publishers.
struct RendererSessionIo {
  /// The camera pose in `world_frame` at the header's frame and stamp (tf mode); a failure drops
  /// the input set.
  std::function<ros_conversions::RendererStatus(
      const std::string& world_frame, const std_msgs::Header& header, Eigen::Matrix4d& pose)>
      camera_pose;
  /// The engine for a thread count, asked for only when a step renders.
  std::function<PointSplatter&(int threads)> splatter;
  /// One rendered frame with its camera's intrinsics at the render size.
  std::function<void(const RenderedFrame& frame, const PinholeIntrinsics& intrinsics,
                     const ImageSize& size, const std_msgs::Header& header)>
      publish;
};

/// What one step did, for the node's counters and logs.
struct RendererStep {
  /// Why the input set was dropped, or the keyframe's cloud had no point (counted per fault).
  ros_conversions::RendererStatus fault;

  bool keyframe = false;  ///< a keyframe was taken
  ros::Time keyframe_stamp;
  std::size_t keyframe_points = 0;
  double keyframe_ms = 0.0;  ///< lifting its cloud

  bool live_frame = false;  ///< the live view was rendered and published
  double render_ms = 0.0;   ///< splatting it
  double frame_ms = 0.0;    ///< since the set arrived, publishing included

  bool burst = false;  ///< the preset burst was rendered and published (and exported)
  int burst_frames = 0;
  double burst_ms = 0.0;
  std::string report;   ///< burstReport of the burst
  std::string warning;  ///< gen3cSizeWarning of the burst's export, if any

  std::string error;  ///< why the burst or the live rendering failed, when one was tried
};

/// The keyframe and its schedule, with the frames a live view renders into. Not thread-safe
/// (onInputSet and renderBurst share the keyframe), except requestKeyframe.
class RendererSession {
 public:
  explicit RendererSession(RendererSessionIo io) : io_(std::move(io)) {}

  /// The next input set becomes the keyframe. Thread-safe.
  void requestKeyframe() { schedule_.request(); }

  /// One synchronized set that arrived at `arrival`, under `settings`. A set that is due
  /// (KeyframeSchedule) becomes the keyframe; in tf mode every set then renders the live view from
  /// the keyframe; in preset mode a new keyframe renders the burst and other sets are only checked.
  RendererStep onInputSet(const sensor_msgs::Image& image, const sensor_msgs::Image& depth,
                          const sensor_msgs::Image& mask, const sensor_msgs::CameraInfo& info,
                          const ConditioningRendererSettings& settings,
                          std::chrono::steady_clock::time_point arrival);

  /// The preset burst from the current keyframe (~render); the step's error says why not.
  RendererStep renderBurst(const ConditioningRendererSettings& settings);

 private:
  bool takeKeyframe(ros_conversions::RendererInput&& input, const Eigen::Matrix4d& camera_to_world,
                    const ConditioningRendererSettings& settings, RendererStep& step);
  const ColoredCloud* keyframeCloud(const ConditioningRendererSettings& settings,
                                    RendererStep& step);
  void renderLive(const ros_conversions::RendererInput& target,
                  const Eigen::Matrix4d& camera_to_world,
                  const ConditioningRendererSettings& settings,
                  std::chrono::steady_clock::time_point arrival, RendererStep& step);
  void burst(const ConditioningRendererSettings& settings, RendererStep& step);

  RendererSessionIo io_;
  std::optional<RendererKeyframe> keyframe_;
  KeyframeSchedule schedule_;
  std::vector<RenderedFrame> frames_;  // reused between live frames
};

}  // namespace multimodal_nvs
