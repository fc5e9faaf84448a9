#pragma once
// The conditioning renderer's keyframe: when a new one is taken, the reference view with its cloud
// kept for the current parameters, and the live view rendered from it.
#include <ros/time.h>

#include <Eigen/Core>
#include <atomic>
#include <optional>

#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"

namespace multimodal_nvs {

/// When the next synchronized input set becomes the keyframe: the first one, the one after a
/// request (~set_keyframe), one whose header time went back (a bag restarted: the keyframe is
/// stale), and, with an interval > 0, the first one at least `interval` seconds of header time
/// after the keyframe.
class KeyframeSchedule {
 public:
  /// Thread-safe (a service callback asks while the frame callback decides).
  void request() { requested_ = true; }
  bool due(const ros::Time& stamp, double interval) const;
  /// A keyframe stamped `stamp` was taken: the request, if any, is served.
  void taken(const ros::Time& stamp);

 private:
  std::atomic<bool> requested_{false};
  std::optional<ros::Time> keyframe_stamp_;
};

/// The reference view every frame is rendered from, with its cloud for the parameters it was last
/// asked for.
class RendererKeyframe {
 public:
  /// Lifts `input` for `settings` into `out` (left as it was when there is no point to lift: the
  /// fault is kNoKeptPixel then).
  static ros_conversions::RendererStatus make(ros_conversions::RendererInput&& input,
                                              const Eigen::Matrix4d& camera_to_world,
                                              const ConditioningRendererSettings& settings,
                                              std::optional<RendererKeyframe>& out);

  /// The cloud for `settings`, lifted again when its depth preparation differs from the cloud's
  /// (a render-size change); nullptr with `status` set when that leaves no point.
  const ColoredCloud* cloudFor(const ConditioningRendererSettings& settings,
                               ros_conversions::RendererStatus& status);

  const ros_conversions::RendererInput& input() const { return input_; }
  /// Identity in preset mode.
  const Eigen::Matrix4d& cameraToWorld() const { return camera_to_world_; }
  const ColoredCloud& cloud() const { return cloud_; }

 private:
  RendererKeyframe() = default;

  ros_conversions::RendererInput input_;
  Eigen::Matrix4d camera_to_world_ = Eigen::Matrix4d::Identity();
  ColoredCloud cloud_;
  BackprojectionParams cloud_params_;  ///< what cloud_ was built with
};

/// The one-view trajectory of the tf mode: the keyframe's cloud seen by the camera of `target`
/// at `camera_to_world`, with the target image's intrinsics scaled to `size`.
Trajectory liveView(const RendererKeyframe& keyframe, const ros_conversions::RendererInput& target,
                    const Eigen::Matrix4d& camera_to_world, const ImageSize& size);

}  // namespace multimodal_nvs
