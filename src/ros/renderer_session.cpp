#include "multimodal_nvs/ros/renderer_session.hpp"

#include <utility>

#include "multimodal_nvs/core/common/elapsed.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/ros/preset_burst.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

RendererStep RendererSession::onInputSet(const sensor_msgs::Image& image,
                                         const sensor_msgs::Image& depth,
                                         const sensor_msgs::Image& mask,
                                         const sensor_msgs::CameraInfo& info,
                                         const ConditioningRendererSettings& settings,
                                         std::chrono::steady_clock::time_point arrival) {
  RendererStep step;
  const bool keyframe = schedule_.due(image.header.stamp, settings.keyframe_interval);
  const bool live = settings.source == TrajectorySource::kTf;
  // Preset mode between keyframes: the set is checked (its faults count), its pixels never read.
  rc::RendererInput input;
  step.fault = rc::rendererInputFromMessages(image, depth, mask, info, keyframe, input);
  if (!step.fault.ok() || (!keyframe && !live)) return step;
  Eigen::Matrix4d camera_to_world = Eigen::Matrix4d::Identity();
  if (live) {
    step.fault = io_.camera_pose(settings.world_frame, input.header, camera_to_world);
    if (!step.fault.ok()) return step;
  }
  if (keyframe) {
    // takeKeyframe moves `input` into the keyframe: render from the keyframe's copy below.
    if (!takeKeyframe(std::move(input), camera_to_world, settings, step)) return step;
    if (!live) {
      burst(settings, step);
      return step;
    }
  }
  renderLive(keyframe ? keyframe_->input() : input, camera_to_world, settings, arrival, step);
  return step;
}

RendererStep RendererSession::renderBurst(const ConditioningRendererSettings& settings) {
  RendererStep step;
  burst(settings, step);
  return step;
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

void RendererSession::renderLive(const rc::RendererInput& target,
                                 const Eigen::Matrix4d& camera_to_world,
                                 const ConditioningRendererSettings& settings,
                                 std::chrono::steady_clock::time_point arrival,
                                 RendererStep& step) {
  const ColoredCloud* cloud = keyframeCloud(settings, step);
  if (!cloud) return;
  const ImageSize size = settings.renderSize();
  const Trajectory view = liveView(*keyframe_, target, camera_to_world, size);
  const auto render_start = std::chrono::steady_clock::now();
  try {
    io_.splatter(settings.threads).render(*cloud, view, 0, 1, settings.splat, frames_);
  } catch (const InputError& e) {  // inputs and parameters were validated: not expected
    step.error = std::string("rendering failed: ") + e.what();
    return;
  }
  step.render_ms = millisecondsSince(render_start);
  io_.publish(frames_[0], view.cameras[0].intrinsics, size, target.header);
  step.live_frame = true;
  step.frame_ms = millisecondsSince(arrival);
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
  step.burst = true;
  step.burst_frames = settings.num_frames;
  step.burst_ms = millisecondsSince(start);
  step.report = burstReport(settings, step.burst_ms, result.gen3c_folder);
}

}  // namespace multimodal_nvs
