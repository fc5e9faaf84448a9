#pragma once
// The conditioning renderer's per-frame steps. A depth set (image, depth, mask, camera_info) is
// checked and taken as the keyframe when due; in preset mode a new keyframe renders the preset
// burst. Every camera image (tf mode) renders the keyframe into the camera's pose at its stamp,
// whether or not a depth set came with it; images that arrive before their keyframe (the depth
// nodelet is slower than the camera) wait in a short history and are rendered once it is taken.
// The same camera frames feed a recorded-trajectory export (renderer_recorded_export.hpp).
// The node counts and logs what each step reports.
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

#include <Eigen/Core>
#include <chrono>
#include <cstddef>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"
#include "multimodal_nvs/ros/renderer_keyframe.hpp"
#include "multimodal_nvs/ros/renderer_recorded_export.hpp"

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
  /// The views of a burst from the keyframe whose header is given (its camera frame and stamp).
  std::function<void(const Trajectory& views, const std_msgs::Header& keyframe_header)> views;
};

/// What one step did, for the node's counters and logs.
struct RendererStep {
  /// Why the input set was dropped, or the keyframe's cloud had no point (counted per fault).
  ros_conversions::RendererStatus fault;

  bool keyframe = false;  ///< a keyframe was taken
  ros::Time keyframe_stamp;
  std::size_t keyframe_points = 0;
  double keyframe_ms = 0.0;  ///< lifting its cloud

  /// A camera frame that was rendered and published: splatting time and time since it arrived.
  struct LiveFrame {
    ros::Time stamp;
    double render_ms = 0.0;
    double frame_ms = 0.0;
  };
  std::vector<LiveFrame> live_frames;
  /// Why camera frames (other than the step's own input) were not rendered, e.g. no tf.
  std::vector<ros_conversions::RendererStatus> frame_faults;
  /// Camera frames recorded (pose, export) but not rendered because newer ones were waiting.
  int live_skipped = 0;

  bool burst = false;  ///< the preset burst was rendered and published (and exported)
  int burst_frames = 0;
  double burst_ms = 0.0;
  std::string report;   ///< burstReport of the burst
  std::string warning;  ///< gen3cSizeWarning of the burst's export, if any

  std::string error;  ///< why the burst or the live rendering failed, when one was tried
};

/// The keyframe and its schedule, the recent camera frames and the export's collection. Not
/// thread-safe (every step shares the keyframe), except requestKeyframe.
class RendererSession {
 public:
  /// Camera frames kept for a keyframe that is still being computed (at 15 Hz, 4 s).
  static constexpr std::size_t kHistoryFrames = 60;

  explicit RendererSession(RendererSessionIo io) : io_(std::move(io)) {}

  /// The next input set becomes the keyframe. Thread-safe.
  void requestKeyframe() { schedule_.request(); }

  /// One synchronized depth set that arrived at `arrival`, under `settings`. A set that is due
  /// (KeyframeSchedule) becomes the keyframe: in tf mode the camera frames waiting for it are then
  /// rendered, in preset mode it renders the burst. Other sets are only checked.
  RendererStep onInputSet(const sensor_msgs::Image& image, const sensor_msgs::Image& depth,
                          const sensor_msgs::Image& mask, const sensor_msgs::CameraInfo& info,
                          const ConditioningRendererSettings& settings,
                          std::chrono::steady_clock::time_point arrival);

  /// One camera image that arrived at `arrival`. In tf mode it is rendered from the keyframe into
  /// the camera pose at its stamp (tf); before the first keyframe, or while the keyframe is newer
  /// than it (a bag loop), it waits in the history. A stamp that goes back clears the history.
  /// With `render_live` false (newer images are already waiting: the renderer is behind) the frame
  /// is recorded as usual (its pose, the export's collection) but not rendered: the live view
  /// skips to the newest image instead of falling further behind, and the export loses no pose.
  RendererStep onCameraImage(const sensor_msgs::Image& image,
                             const ConditioningRendererSettings& settings,
                             std::chrono::steady_clock::time_point arrival,
                             bool render_live = true);

  /// Starts a recorded-trajectory export: the next depth set newer than every camera frame seen so
  /// far becomes the keyframe and the camera poses that follow are collected. The error when the
  /// request is invalid.
  std::optional<std::string> startExport(const RecordedExportRequest& request);
  /// Stops a running collection (a cancel); its stage becomes kAborted with `reason`.
  void abortExport(const std::string& reason);
  const RecordedPoseCollector& exportCollector() const { return collector_; }
  /// The job of a complete collection, with copies of the keyframe and its cloud; the collector is
  /// idle again. False (nothing moved) unless the collection is complete.
  bool takeExportJob(const ConditioningRendererSettings& settings, RecordedExportJob& job);
  /// Clears a reported abort.
  void resetExport() { collector_.reset(); }

  /// The preset burst from the current keyframe (~render); the step's error says why not.
  RendererStep renderBurst(const ConditioningRendererSettings& settings);

 private:
  bool takeKeyframe(ros_conversions::RendererInput&& input, const Eigen::Matrix4d& camera_to_world,
                    const ConditioningRendererSettings& settings, RendererStep& step);
  const ColoredCloud* keyframeCloud(const ConditioningRendererSettings& settings,
                                    RendererStep& step);
  /// A camera frame kept in the history: its header, its pose once looked up, and its live image
  /// at the render size while an export wants ground truth.
  struct CameraFrame {
    std_msgs::Header header;
    std::optional<Eigen::Matrix4d> camera_to_world;
    cv::Mat ground_truth;
    std::chrono::steady_clock::time_point arrival;
  };
  void serveCameraFrame(CameraFrame& frame, const ConditioningRendererSettings& settings,
                        RendererStep& step, ros_conversions::RendererStatus& fault,
                        bool render_live = true);
  void renderLive(const CameraFrame& frame, const ConditioningRendererSettings& settings,
                  RendererStep& step);
  void serveHistory(const ConditioningRendererSettings& settings, RendererStep& step);
  void burst(const ConditioningRendererSettings& settings, RendererStep& step);

  RendererSessionIo io_;
  std::optional<RendererKeyframe> keyframe_;
  KeyframeSchedule schedule_;
  std::vector<RenderedFrame> frames_;  // reused between live frames
  std::deque<CameraFrame> history_;    // the latest camera frames, oldest first
  RecordedPoseCollector collector_;
};

}  // namespace multimodal_nvs
