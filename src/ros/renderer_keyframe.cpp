#include "multimodal_nvs/ros/renderer_keyframe.hpp"

#include <string>
#include <utility>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

bool KeyframeSchedule::due(const ros::Time& stamp, double interval) const {
  if (!keyframe_stamp_ || requested_) return true;
  if (stamp < *keyframe_stamp_) return true;
  return interval > 0.0 && (stamp - *keyframe_stamp_).toSec() >= interval;
}

void KeyframeSchedule::taken(const ros::Time& stamp) {
  keyframe_stamp_ = stamp;
  requested_ = false;
}

namespace {

bool sameBackprojection(const BackprojectionParams& a, const BackprojectionParams& b) {
  return a.resize_to_render == b.resize_to_render && a.render_size == b.render_size &&
         a.max_depth == b.max_depth && a.edge_threshold == b.edge_threshold &&
         a.edge_window == b.edge_window;
}

/// buildColoredCloud of the keyframe's grid, its "no point" InputError as a status.
rc::RendererStatus liftKeyframe(const rc::RendererInput& input, const BackprojectionParams& params,
                                ColoredCloud& cloud) {
  try {
    cloud =
        buildColoredCloud(input.depth, input.kept, input.grid_bgr, input.grid_intrinsics, params);
  } catch (const InputError& e) {
    return rc::RendererStatus::failure(rc::RendererFault::kNoKeptPixel,
                                       std::string("keyframe: ") + e.what());
  }
  return rc::RendererStatus::success();
}

}  // namespace

rc::RendererStatus RendererKeyframe::make(rc::RendererInput&& input,
                                          const Eigen::Matrix4d& camera_to_world,
                                          const ConditioningRendererSettings& settings,
                                          std::optional<RendererKeyframe>& out) {
  RendererKeyframe candidate;
  candidate.cloud_params_ = keyframeBackprojection(settings, input.grid_size);
  const rc::RendererStatus status = liftKeyframe(input, candidate.cloud_params_, candidate.cloud_);
  if (!status.ok()) return status;
  candidate.input_ = std::move(input);
  candidate.camera_to_world_ = camera_to_world;
  out = std::move(candidate);
  return status;
}

const ColoredCloud* RendererKeyframe::cloudFor(const ConditioningRendererSettings& settings,
                                               rc::RendererStatus& status) {
  status = rc::RendererStatus::success();
  const BackprojectionParams params = keyframeBackprojection(settings, input_.grid_size);
  if (sameBackprojection(cloud_params_, params)) return &cloud_;
  status = liftKeyframe(input_, params, cloud_);
  if (!status.ok()) return nullptr;
  cloud_params_ = params;
  return &cloud_;
}

Trajectory liveView(const RendererKeyframe& keyframe, const rc::RendererInput& target,
                    const Eigen::Matrix4d& camera_to_world, const ImageSize& size) {
  Trajectory view;
  view.size = size;
  view.cameras.push_back(
      {relativeWorldToCamera({keyframe.cameraToWorld(), camera_to_world})[1],
       target.image_intrinsics.scaledTo(target.image_size.height, target.image_size.width,
                                        size.height, size.width)});
  return view;
}

}  // namespace multimodal_nvs
