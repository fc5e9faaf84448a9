#include "multimodal_nvs/ros/renderer_session.hpp"

#include <opencv2/imgproc.hpp>
#include <utility>

#include "multimodal_nvs/core/common/elapsed.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/eval/nvs_metrics.hpp"
#include "multimodal_nvs/ros/preset_burst.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

RendererStep RendererSession::onInputSet(const sensor_msgs::Image& image,
                                         const sensor_msgs::Image& depth,
                                         const sensor_msgs::Image& mask,
                                         const sensor_msgs::CameraInfo& info,
                                         const ConditioningRendererSettings& settings,
                                         std::chrono::steady_clock::time_point /*arrival*/) {
  RendererStep step;
  const bool keyframe = schedule_.due(image.header.stamp, settings.keyframe_interval);
  const bool live = settings.source == TrajectorySource::kTf;
  // Between keyframes the set is checked (its faults count), its pixels never read.
  rc::RendererInput input;
  step.fault = rc::rendererInputFromMessages(image, depth, mask, info, keyframe, input);
  if (!step.fault.ok() || !keyframe) return step;
  Eigen::Matrix4d camera_to_world = Eigen::Matrix4d::Identity();
  const bool exporting = collector_.acceptsKeyframe(input.header.stamp);
  if (live || exporting) {
    step.fault = io_.camera_pose(settings.world_frame, input.header, camera_to_world);
    if (!step.fault.ok()) return step;
  }
  if (!takeKeyframe(std::move(input), camera_to_world, settings, step)) return step;
  if (collector_.stage() == RecordedPoseCollector::Stage::kWaitingForKeyframe) {
    if (exporting) {
      collector_.keyframe(
          keyframe_->input().header.stamp, camera_to_world,
          groundTruthAtRenderSize(keyframe_->input().image_bgr, settings.renderSize()));
    } else {
      schedule_.request();  // older than a camera frame seen before the export began
    }
  }
  if (!live) burst(settings, step);
  serveHistory(settings, step);
  return step;
}

RendererStep RendererSession::onCameraImage(const sensor_msgs::Image& image,
                                            const ConditioningRendererSettings& settings,
                                            std::chrono::steady_clock::time_point arrival,
                                            bool render_live) {
  RendererStep step;
  step.fault = rc::fromConversion(rc::validateImage(image), "image");
  if (!step.fault.ok()) return step;
  if (!history_.empty() && image.header.stamp < history_.back().header.stamp) {
    history_.clear();  // the stream restarted (a bag loop): those frames belong to another time
    collector_.abort(
        "camera time went back (a bag loop or a restarted stream) while collecting "
        "the recorded trajectory");
  }
  CameraFrame frame;
  frame.header = image.header;
  frame.arrival = arrival;
  if (collector_.active()) {
    cv::Mat bgr;
    step.fault =
        rc::fromConversion(rc::colourFromImage(image, rc::ChannelOrder::kBgr, bgr), "image");
    if (!step.fault.ok()) return step;
    frame.ground_truth = groundTruthAtRenderSize(bgr, settings.renderSize());
  }
  if (keyframe_ && frame.header.stamp >= keyframe_->input().header.stamp) {
    serveCameraFrame(frame, settings, step, step.fault, render_live);
  }
  history_.push_back(std::move(frame));
  while (history_.size() > kHistoryFrames)
    history_.pop_front();
  return step;
}

/// Renders (tf mode) and collects (export) one camera frame newer than the keyframe; `fault` gets
/// why it could not.
void RendererSession::serveCameraFrame(CameraFrame& frame,
                                       const ConditioningRendererSettings& settings,
                                       RendererStep& step, rc::RendererStatus& fault,
                                       bool render_live) {
  const bool live = settings.source == TrajectorySource::kTf;
  const bool collecting = collector_.stage() == RecordedPoseCollector::Stage::kCollecting;
  if (live && !render_live) ++step.live_skipped;
  const bool render = live && render_live;
  if (!render && !collecting) return;  // a skipped frame needs no pose unless it is collected
  if (!frame.camera_to_world) {
    Eigen::Matrix4d pose;
    fault = io_.camera_pose(settings.world_frame, frame.header, pose);
    if (!fault.ok()) {
      collector_.abort("no camera pose for a frame of the recorded trajectory: " + fault.reason);
      return;
    }
    frame.camera_to_world = pose;
  }
  if (render) renderLive(frame, settings, step);
  if (collecting) {
    collector_.cameraFrame(frame.header.stamp, *frame.camera_to_world, frame.ground_truth);
  }
}

/// A new keyframe: the camera frames from its stamp on that waited in the history.
void RendererSession::serveHistory(const ConditioningRendererSettings& settings,
                                   RendererStep& step) {
  for (CameraFrame& frame : history_) {
    if (frame.header.stamp < keyframe_->input().header.stamp) continue;
    rc::RendererStatus fault;
    serveCameraFrame(frame, settings, step, fault);
    if (!fault.ok()) step.frame_faults.push_back(fault);
  }
}

RendererStep RendererSession::renderBurst(const ConditioningRendererSettings& settings) {
  RendererStep step;
  burst(settings, step);
  return step;
}

std::optional<std::string> RendererSession::startExport(const RecordedExportRequest& request) {
  if (auto error = recordedExportRequestError(request)) return error;
  std::optional<ros::Time> latest_seen;
  if (!history_.empty()) latest_seen = history_.back().header.stamp;
  collector_.start(request, latest_seen);
  schedule_.request();
  return std::nullopt;
}

void RendererSession::abortExport(const std::string& reason) {
  collector_.abort(reason);
}

bool RendererSession::takeExportJob(const ConditioningRendererSettings& settings,
                                    RecordedExportJob& job) {
  if (collector_.stage() != RecordedPoseCollector::Stage::kComplete || !keyframe_) return false;
  RendererStep step;
  const ColoredCloud* cloud = keyframeCloud(settings, step);
  if (!cloud) {
    collector_.abort("the keyframe has no point to render: " + step.fault.reason);
    return false;
  }
  job.poses = collector_.take();
  job.keyframe = keyframe_->input();
  job.cloud = *cloud;
  job.backprojection = keyframeBackprojection(settings, keyframe_->input().grid_size);
  job.settings = settings;
  return true;
}

/// Makes `input` the keyframe if its cloud can be built; otherwise keeps the previous one.
bool RendererSession::takeKeyframe(rc::RendererInput&& input,
                                   const Eigen::Matrix4d& camera_to_world,
                                   const ConditioningRendererSettings& settings,
                                   RendererStep& step) {
  const auto start = std::chrono::steady_clock::now();
  step.fault = RendererKeyframe::make(std::move(input), camera_to_world, settings, keyframe_);
  if (!step.fault.ok()) return false;
  schedule_.taken(keyframe_->input().header.stamp);
  step.keyframe = true;
  step.keyframe_stamp = keyframe_->input().header.stamp;
  step.keyframe_points = keyframe_->cloud().size();
  step.keyframe_ms = millisecondsSince(start);
  return true;
}

/// The keyframe's cloud for the current parameters; nullptr (the fault set) when there is none.
const ColoredCloud* RendererSession::keyframeCloud(const ConditioningRendererSettings& settings,
                                                   RendererStep& step) {
  if (!keyframe_) return nullptr;
  return keyframe_->cloudFor(settings, step.fault);
}

void RendererSession::renderLive(const CameraFrame& frame,
                                 const ConditioningRendererSettings& settings, RendererStep& step) {
  const ColoredCloud* cloud = keyframeCloud(settings, step);
  if (!cloud) return;
  const ImageSize size = settings.renderSize();
  // The camera images share the keyframe's camera: its intrinsics, scaled to the render size.
  const Trajectory view = liveView(*keyframe_, keyframe_->input(), *frame.camera_to_world, size);
  const auto render_start = std::chrono::steady_clock::now();
  try {
    io_.splatter(settings.threads).render(*cloud, view, 0, 1, settings.splat, frames_);
  } catch (const InputError& e) {  // inputs and parameters were validated: not expected
    step.error = std::string("rendering failed: ") + e.what();
    return;
  }
  RendererStep::LiveFrame timing;
  timing.stamp = frame.header.stamp;
  timing.render_ms = millisecondsSince(render_start);
  io_.publish(frames_[0], view.cameras[0].intrinsics, size, frame.header);
  timing.frame_ms = millisecondsSince(frame.arrival);
  step.live_frames.push_back(timing);
}

void RendererSession::burst(const ConditioningRendererSettings& settings, RendererStep& step) {
  const auto start = std::chrono::steady_clock::now();
  const ColoredCloud* cloud = keyframeCloud(settings, step);
  if (!cloud) {
    step.error = burstUnavailableReason(keyframe_.has_value());
    return;
  }
  const PresetBurstResult result = renderPresetBurst(
      io_.splatter(settings.threads), *keyframe_, *cloud, settings,
      [this, &settings](const RenderedFrame& frame, const TargetCamera& camera,
                        const std_msgs::Header& header) {
        io_.publish(frame, camera.intrinsics, settings.renderSize(), header);
      },
      [&step](const std::string& warning) { step.warning = warning; });
  if (!result.ok) {
    step.error = result.error;
    return;
  }
  if (io_.views) io_.views(result.trajectory, keyframe_->input().header);
  step.burst = true;
  step.burst_frames = settings.num_frames;
  step.burst_ms = millisecondsSince(start);
  step.report = burstReport(settings, step.burst_ms, result.gen3c_folder);
}

}  // namespace multimodal_nvs
