// multimodal_nvs/ConditioningRenderer: the camera image with the depth nodelet's kept depth in;
// conditioning frames (colour, hole mask, depth, camera_info, labelled preview) out, rendered from
// a keyframe into the live camera pose from tf, or along a preset trajectory as a burst with an
// optional GEN3C export. Wiring only: conversions live in
// multimodal_nvs/ros/renderer_conversions.hpp, the keyframe policy and cloud in
// ros/renderer_keyframe.hpp, the preset burst in ros/preset_burst.hpp, and rendering in the core's
// burst entry point (core/render/render_burst.hpp, as render_conditioning uses it).
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <pluginlib/class_list_macros.hpp>

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>

#include "conditioning_renderer_diagnostics.hpp"
#include "conditioning_renderer_inputs.hpp"
#include "conditioning_renderer_outputs.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/render/render_burst.hpp"
#include "multimodal_nvs/ros/preset_burst.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"
#include "multimodal_nvs/ros/renderer_keyframe.hpp"
#include "nodelet_state.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

class ConditioningRendererNodelet : public nodelet::Nodelet {
 private:
  using Config = ConditioningRendererConfig;
  using Settings = ConditioningRendererSettings;

  void onInit() override;
  void connectCb();
  void onFrame(const sensor_msgs::ImageConstPtr& image, const sensor_msgs::ImageConstPtr& depth,
               const sensor_msgs::ImageConstPtr& mask, const sensor_msgs::CameraInfoConstPtr& info);
  bool lookupCameraPose(const std::string& world_frame, const std_msgs::Header& header,
                        Eigen::Matrix4d& camera_to_world);
  bool takeKeyframe(rc::RendererInput& input, const Eigen::Matrix4d& camera_to_world,
                    const Settings& settings);
  const ColoredCloud* keyframeCloud(const Settings& settings);
  void renderLive(const rc::RendererInput& target, const Eigen::Matrix4d& camera_to_world,
                  const Settings& settings, std::chrono::steady_clock::time_point start);
  bool renderBurst(const Settings& settings, std::string& report);
  bool onSetKeyframe(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool onRender(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool accept(const rc::RendererStatus& status);
  void reconfigure(Config& config, uint32_t level);

  // Static parameters (read once in onInit).
  int queue_size_ = 5;
  int publisher_queue_size_ = 10;
  ros::Duration tf_timeout_;

  // Inputs (exact-time sync), subscribed only while an output has a subscriber or a preset burst
  // is exported.
  std::unique_ptr<image_transport::ImageTransport> it_;
  std::unique_ptr<ConditioningRendererInputs> inputs_;

  // Outputs. connect_mutex_ also guards their assignment: connect callbacks may fire meanwhile.
  std::mutex connect_mutex_;
  bool advertised_ = false;
  bool subscribed_ = false;
  ConditioningRendererOutputs outputs_;
  ros::ServiceServer set_keyframe_srv_, render_srv_;

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;

  // Written by the reconfigure callback, copied once per frame by the frame callback.
  GuardedSettings<Settings> settings_;
  std::unique_ptr<dynamic_reconfigure::Server<Config>> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;

  // Keyframe and renderer, shared by the frame callback and the ~render service.
  std::mutex state_mutex_;
  std::optional<RendererKeyframe> keyframe_;
  KeyframeSchedule keyframe_schedule_;
  ThreadCountCached<PointSplatter> splatter_;
  std::vector<RenderedFrame> frames_;  // reused between live frames
  PerFaultLogThrottle<rc::kRendererFaultCount> log_throttle_;
  ConditioningRendererDiagnostics diagnostics_;
};

void ConditioningRendererNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  queue_size_ = pnh.param("queue_size", 5);
  publisher_queue_size_ = pnh.param("publisher_queue_size", 10);
  tf_timeout_ = ros::Duration(pnh.param("tf_timeout", 0.1));

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  diagnostics_.start(nh, pnh, getName());

  // The .cfg defaults first; the server then applies the parameter server (YAML) through the same
  // mapping and subscribes the inputs if the settings alone want them (an exported preset).
  settings_.set(rendererSettingsFromConfig(Config::__getDefault__()));
  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  inputs_ = std::make_unique<ConditioningRendererInputs>(
      queue_size_,
      boost::bind(&ConditioningRendererNodelet::onFrame, this, boost::placeholders::_1,
                  boost::placeholders::_2, boost::placeholders::_3, boost::placeholders::_4));
  {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    outputs_.advertise(*it_, static_cast<uint32_t>(std::max(1, publisher_queue_size_)),
                       [this] { connectCb(); });
    advertised_ = true;
  }
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<Config>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(boost::bind(&ConditioningRendererNodelet::reconfigure, this,
                                               boost::placeholders::_1, boost::placeholders::_2));
  set_keyframe_srv_ =
      pnh.advertiseService("set_keyframe", &ConditioningRendererNodelet::onSetKeyframe, this);
  render_srv_ = pnh.advertiseService("render", &ConditioningRendererNodelet::onRender, this);
}

// Lazy subscription (depth_image_proc's idiom): inputs follow the presence of output subscribers,
// or of a preset burst that is exported to disk.
void ConditioningRendererNodelet::connectCb() {
  std::lock_guard<std::mutex> lock(connect_mutex_);
  if (!advertised_) return;
  const bool wanted = presetExportWanted(settings_.get()) || outputs_.anySubscribed();
  if (wanted && !subscribed_) inputs_->subscribe(*it_, getNodeHandle(), getPrivateNodeHandle());
  if (!wanted && subscribed_) inputs_->unsubscribe();
  subscribed_ = wanted;
  diagnostics_.setSubscribed(wanted);
}

void ConditioningRendererNodelet::onFrame(const sensor_msgs::ImageConstPtr& image,
                                          const sensor_msgs::ImageConstPtr& depth,
                                          const sensor_msgs::ImageConstPtr& mask,
                                          const sensor_msgs::CameraInfoConstPtr& info) {
  const auto start = std::chrono::steady_clock::now();
  diagnostics_.countSet();
  const Settings settings = settings_.get();
  std::lock_guard<std::mutex> lock(state_mutex_);
  const bool keyframe = keyframe_schedule_.due(image->header.stamp, settings.keyframe_interval);
  const bool live = settings.source == TrajectorySource::kTf;
  if (!keyframe && !live) {  // preset mode between keyframes: checked and counted, nothing to do
    rc::RendererInput unused;
    accept(rc::rendererInputFromMessages(*image, *depth, *mask, *info, false, unused));
    return;
  }
  rc::RendererInput input;
  if (!accept(rc::rendererInputFromMessages(*image, *depth, *mask, *info, keyframe, input))) return;
  Eigen::Matrix4d camera_to_world = Eigen::Matrix4d::Identity();
  if (live && !lookupCameraPose(settings.world_frame, input.header, camera_to_world)) return;
  if (keyframe) {
    // takeKeyframe moves `input` into the keyframe: render from the keyframe's copy below.
    if (!takeKeyframe(input, camera_to_world, settings)) return;
    if (!live) {
      std::string report;
      if (!renderBurst(settings, report)) NODELET_ERROR_THROTTLE(2.0, "%s", report.c_str());
      return;
    }
  }
  renderLive(keyframe ? keyframe_->input() : input, camera_to_world, settings, start);
}

bool ConditioningRendererNodelet::lookupCameraPose(const std::string& world_frame,
                                                   const std_msgs::Header& header,
                                                   Eigen::Matrix4d& camera_to_world) {
  try {
    camera_to_world =
        tf2::transformToEigen(
            tf_buffer_->lookupTransform(world_frame, header.frame_id, header.stamp, tf_timeout_))
            .matrix();
    return true;
  } catch (const tf2::TransformException& e) {
    return accept(rc::RendererStatus::failure(
        rc::RendererFault::kTransformUnavailable,
        "tf " + world_frame + " -> '" + header.frame_id + "': " + e.what()));
  }
}

/// Makes `input` the keyframe if its cloud can be built; otherwise keeps the previous one.
bool ConditioningRendererNodelet::takeKeyframe(rc::RendererInput& input,
                                               const Eigen::Matrix4d& camera_to_world,
                                               const Settings& settings) {
  const auto start = std::chrono::steady_clock::now();
  if (!accept(RendererKeyframe::make(std::move(input), camera_to_world, settings, keyframe_))) {
    return false;
  }
  keyframe_schedule_.taken(keyframe_->input().header.stamp);
  diagnostics_.countKeyframe(keyframe_->cloud().size(), millisecondsSince(start));
  NODELET_DEBUG("keyframe at %.3f: %zu points", keyframe_->input().header.stamp.toSec(),
                keyframe_->cloud().size());
  return true;
}

/// The keyframe's cloud for the current parameters; nullptr (counted) when there is none.
const ColoredCloud* ConditioningRendererNodelet::keyframeCloud(const Settings& settings) {
  if (!keyframe_) return nullptr;
  rc::RendererStatus status;
  const ColoredCloud* cloud = keyframe_->cloudFor(settings, status);
  accept(status);
  return cloud;
}

void ConditioningRendererNodelet::renderLive(const rc::RendererInput& target,
                                             const Eigen::Matrix4d& camera_to_world,
                                             const Settings& settings,
                                             std::chrono::steady_clock::time_point start) {
  const ColoredCloud* cloud = keyframeCloud(settings);
  if (!cloud) return;
  const ImageSize size = settings.renderSize();
  const Trajectory view = liveView(*keyframe_, target, camera_to_world, size);
  const auto render_start = std::chrono::steady_clock::now();
  try {
    splatter_.forThreads(settings.threads).render(*cloud, view, 0, 1, settings.splat, frames_);
  } catch (const InputError& e) {  // inputs and parameters were validated: not expected
    NODELET_ERROR_THROTTLE(2.0, "rendering failed: %s", e.what());
    return;
  }
  const double render_ms = millisecondsSince(render_start);
  outputs_.publish(frames_[0], view.cameras[0].intrinsics, size, target.header);
  diagnostics_.countFrame(render_ms, millisecondsSince(start));
}

/// The preset burst from the keyframe; `report` says what happened, or why not.
bool ConditioningRendererNodelet::renderBurst(const Settings& settings, std::string& report) {
  const auto start = std::chrono::steady_clock::now();
  const ColoredCloud* cloud = keyframeCloud(settings);
  if (!cloud) {
    report = burstUnavailableReason(keyframe_.has_value());
    return false;
  }
  const PresetBurstResult burst = renderPresetBurst(
      splatter_.forThreads(settings.threads), *keyframe_, *cloud, settings,
      [this, &settings](const RenderedFrame& frame, const TargetCamera& camera,
                        const std_msgs::Header& header) {
        outputs_.publish(frame, camera.intrinsics, settings.renderSize(), header);
      },
      [this](const std::string& warning) { NODELET_WARN_ONCE("%s", warning.c_str()); });
  if (!burst.ok) {
    report = burst.error;
    return false;
  }
  const double burst_ms = millisecondsSince(start);
  diagnostics_.countBurst(settings.num_frames, burst_ms);
  report = burstReport(settings, burst_ms, burst.gen3c_folder);
  NODELET_INFO("%s", report.c_str());
  return true;
}

bool ConditioningRendererNodelet::onSetKeyframe(std_srvs::Trigger::Request&,
                                                std_srvs::Trigger::Response& res) {
  keyframe_schedule_.request();
  res.success = true;
  res.message = "the next synchronized input set becomes the keyframe";
  bool subscribed;
  {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    subscribed = subscribed_;
  }
  if (!subscribed) res.message += " (inputs are not subscribed yet: no output has a subscriber)";
  return true;
}

bool ConditioningRendererNodelet::onRender(std_srvs::Trigger::Request&,
                                           std_srvs::Trigger::Response& res) {
  const Settings settings = settings_.get();
  std::lock_guard<std::mutex> lock(state_mutex_);
  res.success = renderBurst(settings, res.message);
  if (!res.success) NODELET_ERROR("~render: %s", res.message.c_str());
  return true;
}

/// Counts and logs a rejected input, throttled per reason (so that one recurring fault does not
/// hide another); true when `status` is ok. Called with state_mutex_ held.
bool ConditioningRendererNodelet::accept(const rc::RendererStatus& status) {
  if (status.ok()) return true;
  diagnostics_.countFault(status.fault);
  if (log_throttle_.due(status.fault)) {
    NODELET_ERROR("dropping input set: %s [%s]", status.reason.c_str(), rc::toString(status.fault));
  }
  return false;
}

void ConditioningRendererNodelet::reconfigure(Config& config, uint32_t /*level*/) {
  if (const auto error = settings_.reconfigure(config, rendererSettingsFromConfig,
                                               writeRendererSettingsToConfig)) {
    NODELET_ERROR("rejected parameter update (%s); keeping the previous values", error->c_str());
  }
  connectCb();  // trajectory_source and export_dir decide whether the inputs are needed
}

}  // namespace multimodal_nvs

PLUGINLIB_EXPORT_CLASS(multimodal_nvs::ConditioningRendererNodelet, nodelet::Nodelet)
