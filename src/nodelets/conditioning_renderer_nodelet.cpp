// multimodal_nvs/ConditioningRenderer: the camera image with the depth nodelet's kept depth in;
// conditioning frames (colour, hole mask, depth, camera_info, labelled preview) out, rendered from
// a keyframe into the live camera pose from tf, or along a preset trajectory as a burst with an
// optional GEN3C export. Wiring only: what a frame does is ros/renderer_session.hpp (conversions in
// ros/renderer_conversions.hpp, the keyframe policy and cloud in ros/renderer_keyframe.hpp, the
// preset burst in ros/preset_burst.hpp, rendering in the core's core/render/render_burst.hpp).
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

#include "conditioning_renderer_diagnostics.hpp"
#include "conditioning_renderer_inputs.hpp"
#include "conditioning_renderer_outputs.hpp"
#include "multimodal_nvs/ros/preset_burst.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"
#include "multimodal_nvs/ros/renderer_session.hpp"
#include "nodelet_state.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

class ConditioningRendererNodelet : public nodelet::Nodelet {
 private:
  using Config = ConditioningRendererConfig;
  using Settings = ConditioningRendererSettings;

  void onInit() override;
  void connectCb();
  void onFrame(const sensor_msgs::ImageConstPtr& image, const sensor_msgs::ImageConstPtr& depth,
               const sensor_msgs::ImageConstPtr& mask, const sensor_msgs::CameraInfoConstPtr& info);
  rc::RendererStatus lookupCameraPose(const std::string& world_frame,
                                      const std_msgs::Header& header,
                                      Eigen::Matrix4d& camera_to_world);
  bool onSetKeyframe(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool onRender(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  void count(const RendererStep& step);
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
  std::unique_ptr<RendererSession> session_;
  ThreadCountCached<PointSplatter> splatter_;
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
  session_ = std::make_unique<RendererSession>(RendererSessionIo{
      [this](const std::string& world_frame, const std_msgs::Header& header,
             Eigen::Matrix4d& pose) { return lookupCameraPose(world_frame, header, pose); },
      [this](int threads) -> PointSplatter& { return splatter_.forThreads(threads); },
      [this](const RenderedFrame& frame, const PinholeIntrinsics& intrinsics, const ImageSize& size,
             const std_msgs::Header& header) {
        outputs_.publish(frame, intrinsics, size, header);
      }});

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
    const image_transport::SubscriberStatusCallback image_cb =
        boost::bind(&ConditioningRendererNodelet::connectCb, this);
    const ros::SubscriberStatusCallback info_cb =
        boost::bind(&ConditioningRendererNodelet::connectCb, this);
    outputs_.advertise(*it_, static_cast<uint32_t>(std::max(1, publisher_queue_size_)), image_cb,
                       info_cb);
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
  const auto arrival = std::chrono::steady_clock::now();
  diagnostics_.countSet();
  const Settings settings = settings_.get();
  std::lock_guard<std::mutex> lock(state_mutex_);
  const RendererStep step = session_->onInputSet(*image, *depth, *mask, *info, settings, arrival);
  count(step);
  if (!step.error.empty()) NODELET_ERROR_THROTTLE(2.0, "%s", step.error.c_str());
}

rc::RendererStatus ConditioningRendererNodelet::lookupCameraPose(const std::string& world_frame,
                                                                 const std_msgs::Header& header,
                                                                 Eigen::Matrix4d& camera_to_world) {
  try {
    camera_to_world =
        tf2::transformToEigen(
            tf_buffer_->lookupTransform(world_frame, header.frame_id, header.stamp, tf_timeout_))
            .matrix();
    return rc::RendererStatus::success();
  } catch (const tf2::TransformException& e) {
    return rc::RendererStatus::failure(
        rc::RendererFault::kTransformUnavailable,
        "tf " + world_frame + " -> '" + header.frame_id + "': " + e.what());
  }
}

bool ConditioningRendererNodelet::onSetKeyframe(std_srvs::Trigger::Request&,
                                                std_srvs::Trigger::Response& res) {
  session_->requestKeyframe();
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
  const RendererStep step = session_->renderBurst(settings);
  count(step);
  res.success = step.burst;
  res.message = step.burst ? step.report : step.error;
  if (!res.success) NODELET_ERROR("~render: %s", res.message.c_str());
  return true;
}

/// Counts and logs what a step did; a rejected input set is logged throttled per reason (so that
/// one recurring fault does not hide another). Called with state_mutex_ held.
void ConditioningRendererNodelet::count(const RendererStep& step) {
  if (!step.fault.ok()) {
    diagnostics_.countFault(step.fault.fault);
    if (log_throttle_.due(step.fault.fault)) {
      NODELET_ERROR("dropping input set: %s [%s]", step.fault.reason.c_str(),
                    rc::toString(step.fault.fault));
    }
  }
  if (step.keyframe) {
    diagnostics_.countKeyframe(step.keyframe_points, step.keyframe_ms);
    NODELET_DEBUG("keyframe at %.3f: %zu points", step.keyframe_stamp.toSec(),
                  step.keyframe_points);
  }
  if (step.live_frame) diagnostics_.countFrame(step.render_ms, step.frame_ms);
  if (!step.warning.empty()) NODELET_WARN_ONCE("%s", step.warning.c_str());
  if (step.burst) {
    diagnostics_.countBurst(step.burst_frames, step.burst_ms);
    NODELET_INFO("%s", step.report.c_str());
  }
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
