// multimodal_nvs/ConditioningRenderer: the camera image with the depth nodelet's kept depth in;
// conditioning frames (colour, hole mask, depth, camera_info, labelled preview) out, rendered from
// a keyframe into the live camera pose from tf, or along a preset trajectory as a burst with an
// optional GEN3C export. Wiring only: conversions live in
// multimodal_nvs/ros/renderer_conversions.hpp and the algorithm in the core (buildColoredCloud,
// presetTrajectory, PointSplatter, fillHolesPushPull, Gen3cExportWriter), used as the
// render_conditioning tool uses them.
#include <dynamic_reconfigure/server.h>
#include <image_transport/camera_publisher.h>
#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/subscriber.h>
#include <message_filters/time_synchronizer.h>
#include <nodelet/nodelet.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <pluginlib/class_list_macros.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>

#include "conditioning_renderer_diagnostics.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/gen3c_export.hpp"
#include "multimodal_nvs/core/render/preview.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"
#include "nodelet_state.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

bool sameBackprojection(const BackprojectionParams& a, const BackprojectionParams& b) {
  return a.resize_to_render == b.resize_to_render && a.render_size == b.render_size &&
         a.max_depth == b.max_depth && a.edge_threshold == b.edge_threshold &&
         a.edge_window == b.edge_window;
}

/// EXPORT_DIR/<sec>_<nsec>: one GEN3C folder per keyframe.
std::string exportFolder(const std::string& export_dir, const ros::Time& stamp) {
  char name[32];
  std::snprintf(name, sizeof name, "%010u_%09u", stamp.sec, stamp.nsec);
  return export_dir + "/" + name;
}

}  // namespace

class ConditioningRendererNodelet : public nodelet::Nodelet {
 private:
  using Config = ConditioningRendererConfig;
  using Settings = ConditioningRendererSettings;
  using Image = sensor_msgs::Image;
  using Sync = message_filters::TimeSynchronizer<Image, Image, Image, sensor_msgs::CameraInfo>;

  /// The reference view every frame is rendered from, with its cloud for the current parameters.
  struct Keyframe {
    rc::RendererInput input;
    Eigen::Matrix4d camera_to_world = Eigen::Matrix4d::Identity();  ///< identity in preset mode
    ColoredCloud cloud;
    BackprojectionParams cloud_params;  ///< what `cloud` was built with
  };

  void onInit() override;
  void advertiseOutputs();
  void connectCb();
  bool inputsWanted();
  void onFrame(const sensor_msgs::ImageConstPtr& image, const sensor_msgs::ImageConstPtr& depth,
               const sensor_msgs::ImageConstPtr& mask, const sensor_msgs::CameraInfoConstPtr& info);
  bool wantsKeyframe(const Settings& settings, const ros::Time& stamp) const;
  bool lookupCameraPose(const std::string& world_frame, const std_msgs::Header& header,
                        Eigen::Matrix4d& camera_to_world);
  bool takeKeyframe(rc::RendererInput& input, const Eigen::Matrix4d& camera_to_world,
                    const Settings& settings);
  const ColoredCloud* keyframeCloud(const Settings& settings);
  void renderLive(const rc::RendererInput& target, const Eigen::Matrix4d& camera_to_world,
                  const Settings& settings, std::chrono::steady_clock::time_point start);
  bool renderBurst(const Settings& settings, std::string& report);
  void publishFrame(const RenderedFrame& frame, const PinholeIntrinsics& intrinsics,
                    const ImageSize& size, const std_msgs::Header& header);
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
  image_transport::SubscriberFilter image_sub_, depth_sub_, mask_sub_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_sub_;
  std::unique_ptr<Sync> sync_;

  // Outputs. connect_mutex_ also guards their assignment: connect callbacks may fire meanwhile.
  std::mutex connect_mutex_;
  bool advertised_ = false;
  bool subscribed_ = false;
  image_transport::CameraPublisher image_pub_;  // conditioning/image + conditioning/camera_info
  image_transport::Publisher mask_pub_, depth_pub_, preview_pub_;
  ros::ServiceServer set_keyframe_srv_, render_srv_;

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;

  // Written by the reconfigure callback, copied once per frame by the frame callback.
  GuardedSettings<Settings> settings_;
  std::unique_ptr<dynamic_reconfigure::Server<Config>> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;

  // Keyframe and renderer, shared by the frame callback and the ~render service.
  std::mutex state_mutex_;
  std::optional<Keyframe> keyframe_;
  std::atomic<bool> keyframe_requested_{false};
  ThreadCountCached<PointSplatter> splatter_;
  std::vector<RenderedFrame> frames_;  // reused between calls
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
  sync_ = std::make_unique<Sync>(image_sub_, depth_sub_, mask_sub_, info_sub_, queue_size_);
  sync_->registerCallback(boost::bind(&ConditioningRendererNodelet::onFrame, this,
                                      boost::placeholders::_1, boost::placeholders::_2,
                                      boost::placeholders::_3, boost::placeholders::_4));
  advertiseOutputs();
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<Config>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(boost::bind(&ConditioningRendererNodelet::reconfigure, this,
                                               boost::placeholders::_1, boost::placeholders::_2));
  set_keyframe_srv_ =
      pnh.advertiseService("set_keyframe", &ConditioningRendererNodelet::onSetKeyframe, this);
  render_srv_ = pnh.advertiseService("render", &ConditioningRendererNodelet::onRender, this);
}

void ConditioningRendererNodelet::advertiseOutputs() {
  image_transport::SubscriberStatusCallback image_cb =
      boost::bind(&ConditioningRendererNodelet::connectCb, this);
  ros::SubscriberStatusCallback info_cb =
      boost::bind(&ConditioningRendererNodelet::connectCb, this);
  std::lock_guard<std::mutex> lock(connect_mutex_);
  const uint32_t q = static_cast<uint32_t>(std::max(1, publisher_queue_size_));
  image_pub_ = it_->advertiseCamera("conditioning/image", q, image_cb, image_cb, info_cb, info_cb);
  mask_pub_ = it_->advertise("conditioning/mask", q, image_cb, image_cb);
  depth_pub_ = it_->advertise("conditioning/depth", q, image_cb, image_cb);
  preview_pub_ = it_->advertise("conditioning/preview", q, image_cb, image_cb);
  advertised_ = true;
}

/// Outputs with subscribers, or a preset burst that is exported to disk.
bool ConditioningRendererNodelet::inputsWanted() {
  const Settings settings = settings_.get();
  if (settings.source == TrajectorySource::kPreset && !settings.export_dir.empty()) return true;
  return image_pub_.getNumSubscribers() > 0 || mask_pub_.getNumSubscribers() > 0 ||
         depth_pub_.getNumSubscribers() > 0 || preview_pub_.getNumSubscribers() > 0;
}

// Lazy subscription (depth_image_proc's idiom): inputs follow the presence of output subscribers.
void ConditioningRendererNodelet::connectCb() {
  std::lock_guard<std::mutex> lock(connect_mutex_);
  if (!advertised_) return;
  const bool wanted = inputsWanted();
  if (wanted && !subscribed_) {
    ros::NodeHandle& nh = getNodeHandle();
    // One message per topic waits for the frame callback (the newest wins); pairing slack lives
    // in the synchronizer's own queue (queue_size).
    image_transport::TransportHints hints("raw", ros::TransportHints(), getPrivateNodeHandle());
    image_sub_.subscribe(*it_, "image", 1, hints);
    depth_sub_.subscribe(*it_, "depth/image", 1, hints);
    mask_sub_.subscribe(*it_, "depth/mask", 1, hints);
    info_sub_.subscribe(nh, "depth/camera_info", 1);
  } else if (!wanted && subscribed_) {
    image_sub_.unsubscribe();
    depth_sub_.unsubscribe();
    mask_sub_.unsubscribe();
    info_sub_.unsubscribe();
  }
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
  const bool keyframe = wantsKeyframe(settings, image->header.stamp);
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
  renderLive(keyframe ? keyframe_->input : input, camera_to_world, settings, start);
}

bool ConditioningRendererNodelet::wantsKeyframe(const Settings& settings,
                                                const ros::Time& stamp) const {
  if (!keyframe_ || keyframe_requested_) return true;
  const ros::Time& key_stamp = keyframe_->input.header.stamp;
  if (stamp < key_stamp) return true;  // time went back (a bag restarted): the keyframe is stale
  return settings.keyframe_interval > 0.0 &&
         (stamp - key_stamp).toSec() >= settings.keyframe_interval;
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
  Keyframe candidate;
  candidate.cloud_params = keyframeBackprojection(settings, input.grid_size);
  try {
    candidate.cloud = buildColoredCloud(input.depth, input.kept, input.grid_bgr,
                                        input.grid_intrinsics, candidate.cloud_params);
  } catch (const InputError& e) {
    return accept(rc::RendererStatus::failure(rc::RendererFault::kNoKeptPixel,
                                              std::string("keyframe: ") + e.what()));
  }
  candidate.input = std::move(input);
  candidate.camera_to_world = camera_to_world;
  keyframe_ = std::move(candidate);
  keyframe_requested_ = false;
  diagnostics_.countKeyframe(keyframe_->cloud.size(), millisecondsSince(start));
  NODELET_DEBUG("keyframe at %.3f: %zu points", keyframe_->input.header.stamp.toSec(),
                keyframe_->cloud.size());
  return true;
}

/// The keyframe's cloud for the current parameters (rebuilt after a render-size change).
const ColoredCloud* ConditioningRendererNodelet::keyframeCloud(const Settings& settings) {
  if (!keyframe_) return nullptr;
  Keyframe& key = *keyframe_;
  const BackprojectionParams params = keyframeBackprojection(settings, key.input.grid_size);
  if (!sameBackprojection(key.cloud_params, params)) {
    try {
      key.cloud = buildColoredCloud(key.input.depth, key.input.kept, key.input.grid_bgr,
                                    key.input.grid_intrinsics, params);
      key.cloud_params = params;
    } catch (const InputError& e) {
      accept(rc::RendererStatus::failure(rc::RendererFault::kNoKeptPixel,
                                         std::string("keyframe: ") + e.what()));
      return nullptr;
    }
  }
  return &key.cloud;
}

void ConditioningRendererNodelet::renderLive(const rc::RendererInput& target,
                                             const Eigen::Matrix4d& camera_to_world,
                                             const Settings& settings,
                                             std::chrono::steady_clock::time_point start) {
  const ColoredCloud* cloud = keyframeCloud(settings);
  if (!cloud) return;
  const ImageSize size = settings.renderSize();
  Trajectory view;
  view.size = size;
  view.cameras.push_back(
      {relativeWorldToCamera({keyframe_->camera_to_world, camera_to_world})[1],
       target.image_intrinsics.scaledTo(target.image_size.height, target.image_size.width,
                                        size.height, size.width)});
  const auto render_start = std::chrono::steady_clock::now();
  try {
    splatter_.forThreads(settings.threads).render(*cloud, view, 0, 1, settings.splat, frames_);
  } catch (const InputError& e) {  // inputs and parameters were validated: not expected
    NODELET_ERROR_THROTTLE(2.0, "rendering failed: %s", e.what());
    return;
  }
  const double render_ms = millisecondsSince(render_start);
  publishFrame(frames_[0], view.cameras[0].intrinsics, size, target.header);
  diagnostics_.countFrame(render_ms, millisecondsSince(start));
}

/// The preset trajectory from the keyframe, published frame by frame (frame i stamped keyframe
/// stamp + i / burst_frame_rate) and, with export_dir, written as a GEN3C folder. `report` says
/// what happened, or why not.
bool ConditioningRendererNodelet::renderBurst(const Settings& settings, std::string& report) {
  const auto start = std::chrono::steady_clock::now();
  const ColoredCloud* cloud = keyframeCloud(settings);
  if (!cloud) {
    report = keyframe_ ? "the keyframe has no point to render"
                       : "no keyframe yet (inputs are subscribed only while an output has a "
                         "subscriber or a preset export_dir is set)";
    return false;
  }
  const rc::RendererInput& key = keyframe_->input;
  const ImageSize size = settings.renderSize();
  const int n = settings.num_frames;
  std::string folder;
  try {
    const Trajectory trajectory =
        presetTrajectory(settings.preset, settings.magnitude, n,
                         key.image_intrinsics.scaledTo(key.image_size.height, key.image_size.width,
                                                       size.height, size.width),
                         size, cloud->medianDepth());
    std::unique_ptr<Gen3cExportWriter> writer;
    std::string partial;
    if (!settings.export_dir.empty()) {
      if (n != kGen3cFrames || size.height != kGen3cHeight || size.width != kGen3cWidth) {
        NODELET_WARN_ONCE(
            "GEN3C expects 121 frames at 704x1280; the export uses the requested %d "
            "frames at %dx%d",
            n, size.height, size.width);
      }
      // Written under a temporary name and renamed when complete: readers never see half a folder.
      folder = exportFolder(settings.export_dir, key.header.stamp);
      partial = folder + ".partial";
      std::filesystem::remove_all(partial);
      writer = std::make_unique<Gen3cExportWriter>(partial, n, size);
      writeGen3cCompanions(partial, key.image_bgr, n, size);
    }
    PointSplatter& renderer = splatter_.forThreads(settings.threads);
    // Chunks keep memory bounded (a gen3c frame holds ~20 MB at 704x1280) and use every core.
    const int chunk = 2 * renderer.threads();
    std_msgs::Header header = key.header;
    for (int first = 0; first < n; first += chunk) {
      const int count = std::min(chunk, n - first);
      renderer.render(*cloud, trajectory, first, count, settings.splat, frames_);
      for (int i = 0; i < count; ++i) {
        const int index = first + i;
        header.stamp = key.header.stamp + ros::Duration(index / settings.burst_frame_rate);
        const TargetCamera& camera = trajectory.cameras[static_cast<std::size_t>(index)];
        publishFrame(frames_[static_cast<std::size_t>(i)], camera.intrinsics, size, header);
        if (writer) writer->append(frames_[static_cast<std::size_t>(i)]);
      }
    }
    if (writer) {
      writer->finish();
      writer.reset();
      std::filesystem::remove_all(folder);
      std::filesystem::rename(partial, folder);
    }
  } catch (const InputError& e) {
    report = std::string("preset burst failed: ") + e.what();
    return false;
  } catch (const std::filesystem::filesystem_error& e) {
    report = std::string("GEN3C export failed: ") + e.what();
    return false;
  }
  const double burst_ms = millisecondsSince(start);
  diagnostics_.countBurst(n, burst_ms);
  char text[160];
  std::snprintf(text, sizeof text, "rendered %d frames at %dx%d (%s %g %s, %s) in %.0f ms", n,
                size.height, size.width, toString(settings.preset).c_str(), settings.magnitude,
                magnitudeUnit(settings.preset).c_str(), toString(settings.splat.mode).c_str(),
                burst_ms);
  report = text;
  if (!folder.empty()) report += "; GEN3C folder " + folder;
  NODELET_INFO("%s", report.c_str());
  return true;
}

/// Publishes the outputs that have subscribers; the preview is computed only when wanted.
void ConditioningRendererNodelet::publishFrame(const RenderedFrame& frame,
                                               const PinholeIntrinsics& intrinsics,
                                               const ImageSize& size,
                                               const std_msgs::Header& header) {
  if (image_pub_.getNumSubscribers() > 0) {
    image_pub_.publish(rc::rgbImageFromBgr(frame.bgr, header),
                       rc::renderedCameraInfo(intrinsics, size, header));
  }
  if (mask_pub_.getNumSubscribers() > 0) mask_pub_.publish(rc::monoImage(frame.mask, header));
  if (depth_pub_.getNumSubscribers() > 0) {
    depth_pub_.publish(rc::renderedDepthImage(frame.depth, frame.mask, header));
  }
  if (preview_pub_.getNumSubscribers() > 0) {
    cv::Mat preview = fillHolesPushPull(frame.bgr, frame.mask);
    drawPreviewLabel(preview);
    preview_pub_.publish(rc::rgbImageFromBgr(preview, header));
  }
}

bool ConditioningRendererNodelet::onSetKeyframe(std_srvs::Trigger::Request&,
                                                std_srvs::Trigger::Response& res) {
  keyframe_requested_ = true;
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
