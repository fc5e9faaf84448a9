#pragma once
// The conditioning renderer's recorded-trajectory export (the paper's experiment from a live
// stream): a new keyframe, the camera poses that follow it on tf collected with their live images,
// resampled to GEN3C's frame count (REFERENCE.md section 4) and rendered into a folder laid out as
// render_conditioning's output: gen3c/ (the arrays the diffusion stage loads), metrics.json
// against the live images at the recorded poses, and keyframe/ with the keyframe's image, depth,
// kept mask and poses plus the render_conditioning command that reproduces gen3c/ byte for byte.
#include <ros/time.h>

#include <Eigen/Core>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "multimodal_nvs/core/render/gen3c_export.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"
#include "multimodal_nvs/ros/renderer_keyframe.hpp"

namespace multimodal_nvs {

/// What an export goal asks for: stop after `num_poses` camera poses (the keyframe's included) or,
/// with `duration` > 0, after the poses within `duration` seconds of header time of the keyframe.
struct RecordedExportRequest {
  int num_poses = 16;
  double duration = 0.0;
  int num_frames = kGen3cFrames;
  std::string output_dir;  ///< the export goes to OUTPUT_DIR/<keyframe stamp>/
};

/// Why a request cannot be served; nullopt when it can.
std::optional<std::string> recordedExportRequestError(const RecordedExportRequest& request);

/// The recorded poses of one export, the keyframe's first, each with its live image at the render
/// size (the ground truth of the metrics; empty where none was kept).
struct RecordedPoses {
  RecordedExportRequest request;
  std::vector<ros::Time> stamps;
  std::vector<Eigen::Matrix4d> camera_to_world;
  std::vector<cv::Mat> ground_truth;
};

/// Collects the camera poses that follow a keyframe taken after the request. Stages: idle ->
/// waiting for a keyframe -> collecting -> complete (or aborted, with the reason). Not thread-safe
/// (the renderer session calls it under its lock).
class RecordedPoseCollector {
 public:
  enum class Stage { kIdle, kWaitingForKeyframe, kCollecting, kComplete, kAborted };

  /// Starts a collection (a running one is dropped). Camera frames up to `latest_seen` were
  /// received before the request: a keyframe must be newer than that.
  void start(const RecordedExportRequest& request, const std::optional<ros::Time>& latest_seen);
  /// Whether a keyframe stamped `stamp` may start the collection.
  bool acceptsKeyframe(const ros::Time& stamp) const;
  /// The keyframe's pose and image (at the render size): pose 0.
  void keyframe(const ros::Time& stamp, const Eigen::Matrix4d& camera_to_world,
                const cv::Mat& ground_truth);
  /// A camera frame; frames at or before the keyframe stamp are ignored, one whose stamp goes
  /// back from the last collected one aborts (a bag loop or a restarted stream).
  void cameraFrame(const ros::Time& stamp, const Eigen::Matrix4d& camera_to_world,
                   const cv::Mat& ground_truth);
  void abort(const std::string& reason);

  Stage stage() const { return stage_; }
  bool active() const {
    return stage_ == Stage::kWaitingForKeyframe || stage_ == Stage::kCollecting;
  }
  int collected() const { return static_cast<int>(poses_.stamps.size()); }
  const std::string& abortReason() const { return abort_reason_; }
  const RecordedExportRequest& request() const { return poses_.request; }
  /// The complete collection; the collector is idle afterwards.
  RecordedPoses take();
  /// Back to idle after an abort has been reported.
  void reset();

 private:
  Stage stage_ = Stage::kIdle;
  std::optional<ros::Time> not_after_;
  RecordedPoses poses_;
  std::string abort_reason_;
};

/// The name of frame j's pose file under keyframe/poses/ and the key it is stored under (VoD's
/// layout: one JSON object, WORLDToCamera = the camera pose in world_frame, row-major 4x4).
std::string recordedPoseKey(const std::string& world_frame);

/// Everything the export renders from, copied out of the session so that rendering runs without
/// its lock.
struct RecordedExportJob {
  RecordedPoses poses;
  ros_conversions::RendererInput keyframe;  ///< the keyframe's messages, converted
  ColoredCloud cloud;                       ///< its cloud for `settings`
  BackprojectionParams backprojection;      ///< what the cloud was lifted with
  ConditioningRendererSettings settings;
};

struct RecordedExportResult {
  bool ok = false;
  bool cancelled = false;
  std::string folder;  ///< where the export is, when ok
  std::string error;
  Trajectory trajectory;  ///< the rendered views (for their tf frames), when ok
};

/// OUTPUT_DIR/<keyframe stamp>/ (gen3cExportFolder's name), written under FOLDER.partial and
/// renamed when complete; a failed or cancelled export removes FOLDER.partial. `progress` gets
/// (frames written, frames in all) after every frame; `cancelled` is asked before the burst and
/// after every frame.
RecordedExportResult exportRecordedTrajectory(PointSplatter& splatter, const RecordedExportJob& job,
                                              const std::function<void(int, int)>& progress,
                                              const std::function<bool()>& cancelled);

}  // namespace multimodal_nvs
