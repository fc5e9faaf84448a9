// multimodal_nvs/DepthCompletion: synchronized PointCloud2 + Image + CameraInfo in; REP-118 depth,
// variance, mask, colour-mapped depth and standard deviation, coloured cloud and stats out. Wiring
// only: topics, parameters, tf, diagnostics and one completeDepthFrame per set. Input policies live
// in multimodal_nvs/ros (the restartable synchronizer, the input timeline, conversions), cost
// policies in the core's workspace.
#include <dynamic_reconfigure/server.h>
#include <image_transport/camera_publisher.h>
#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/subscriber.h>
#include <nodelet/nodelet.h>
#include <sensor_msgs/CompressedImage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <pluginlib/class_list_macros.hpp>

#include <memory>
#include <mutex>
#include <string>

#include "depth_completion_diagnostics.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/depth_completion_workspace.hpp"
#include "multimodal_nvs/ros/conversions.hpp"
#include "multimodal_nvs/ros/depth_color_images.hpp"
#include "multimodal_nvs/ros/depth_completion_config.hpp"
#include "multimodal_nvs/ros/depth_frame.hpp"
#include "multimodal_nvs/ros/frame_synchronizer.hpp"
#include "multimodal_nvs/ros/input_timeline.hpp"
#include "multimodal_nvs/ros/recycled_message.hpp"
#include "multimodal_nvs/ros/stats_message.hpp"
#include "nodelet_state.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

class DepthCompletionNodelet : public nodelet::Nodelet {
 private:
  using Config = DepthCompletionConfig;

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    sync_settings_.queue_size = pnh.param("queue_size", 5);
    sync_settings_.approximate = pnh.param("approximate_sync", true);
    sync_settings_.max_interval = pnh.param("max_interval", 0.0);
    sync_settings_.age_penalty = pnh.param("sync_age_penalty", SyncSettings{}.age_penalty);
    sync_settings_.period_bound_fraction =
        pnh.param("sync_period_bound_fraction", SyncSettings{}.period_bound_fraction);
    const std::string sync_problem = syncSettingsProblem(sync_settings_);
    if (!sync_problem.empty()) {
      const SyncSettings defaults;
      NODELET_ERROR(
          "%s Using the defaults (queue_size %d, max_interval %g, sync_age_penalty %g, "
          "sync_period_bound_fraction %g).",
          sync_problem.c_str(), defaults.queue_size, defaults.max_interval, defaults.age_penalty,
          defaults.period_bound_fraction);
      const bool approximate = sync_settings_.approximate;
      sync_settings_ = defaults;
      sync_settings_.approximate = approximate;
    }
    compressed_input_ = pnh.param("compressed_input", false);
    cloud_to_camera_.timeout = ros::Duration(pnh.param("tf_timeout", 0.1));
    cloud_to_camera_.fixed_frame = pnh.param("fixed_frame", std::string());
    ground_from_tf_.timeout = cloud_to_camera_.timeout;
    ground_from_tf_.frame = pnh.param("ground_frame", std::string());
    max_points_ = pnh.param("max_points", 0);
    readColorScales(pnh);

    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
    diagnostics_.start(nh, pnh, getName());

    // The .cfg defaults, then what the parameter server (YAML) holds, through one mapping.
    settings_.set(settingsFromConfig(Config::__getDefault__()));
    reconfigure_server_ =
        std::make_unique<dynamic_reconfigure::Server<Config>>(reconfigure_mutex_, pnh);
    reconfigure_server_->setCallback(boost::bind(&DepthCompletionNodelet::reconfigure, this,
                                                 boost::placeholders::_1, boost::placeholders::_2));

    it_ = std::make_unique<image_transport::ImageTransport>(nh);
    const auto watch = [this](FrameInput input) { watchInput(input); };
    using namespace boost::placeholders;
    if (compressed_input_) {
      sync_ = std::make_unique<RestartableFrameSynchronizer<sensor_msgs::CompressedImage>>(
          sync_settings_, points_sub_, compressed_sub_, info_sub_, watch,
          boost::bind(&DepthCompletionNodelet::onFrame<sensor_msgs::CompressedImage>, this, _1, _2,
                      _3));
    } else {
      sync_ = std::make_unique<RestartableFrameSynchronizer<sensor_msgs::Image>>(
          sync_settings_, points_sub_, image_sub_, info_sub_, watch,
          boost::bind(&DepthCompletionNodelet::onFrame<sensor_msgs::Image>, this, _1, _2, _3));
    }
    advertiseOutputs();
  }

  /// The fixed ranges (metres) of the colour images: a colour is the same distance in every frame.
  void readColorScales(ros::NodeHandle& pnh) {
    const double depth_max = pnh.param("depth_color_max", kDefaultDepthColorMax);
    const double stddev_max = pnh.param("stddev_color_max", kDefaultStddevColorMax);
    try {
      depth_scale_ = ColorScale(0.0, depth_max, cv::COLORMAP_TURBO);
      stddev_scale_ = ColorScale(0.0, stddev_max, cv::COLORMAP_VIRIDIS);
    } catch (const InputError& e) {
      NODELET_ERROR("depth_color_max %g / stddev_color_max %g must be > 0 (%s): using %g / %g m",
                    depth_max, stddev_max, e.what(), kDefaultDepthColorMax, kDefaultStddevColorMax);
    }
  }

  void advertiseOutputs() {
    ros::NodeHandle& nh = getNodeHandle();
    image_transport::SubscriberStatusCallback image_cb =
        boost::bind(&DepthCompletionNodelet::connectCb, this);
    ros::SubscriberStatusCallback topic_cb = boost::bind(&DepthCompletionNodelet::connectCb, this);
    std::lock_guard<std::mutex> lock(connect_mutex_);
    depth_pub_ = it_->advertiseCamera("depth/image", 1, image_cb, image_cb, topic_cb, topic_cb);
    variance_pub_ = it_->advertise("depth/variance", 1, image_cb, image_cb);
    mask_pub_ = it_->advertise("depth/mask", 1, image_cb, image_cb);
    // For people (rviz); on the grid of depth/image, so depth/camera_info describes them too.
    depth_color_pub_ = it_->advertise("depth/image_color", 1, image_cb, image_cb);
    stddev_color_pub_ = it_->advertise("depth/stddev_color", 1, image_cb, image_cb);
    points_pub_ = nh.advertise<sensor_msgs::PointCloud2>("depth/points", 1, topic_cb, topic_cb);
    stats_pub_ = nh.advertise<DepthCompletionStats>("depth/stats", 5, topic_cb, topic_cb);
    ground_plane_pub_ =
        nh.advertise<geometry_msgs::PolygonStamped>("depth/ground_plane", 5, topic_cb, topic_cb);
  }

  bool outputsHaveSubscribers() const {
    return depth_pub_.getNumSubscribers() > 0 || variance_pub_.getNumSubscribers() > 0 ||
           mask_pub_.getNumSubscribers() > 0 || depth_color_pub_.getNumSubscribers() > 0 ||
           stddev_color_pub_.getNumSubscribers() > 0 || points_pub_.getNumSubscribers() > 0 ||
           stats_pub_.getNumSubscribers() > 0 || ground_plane_pub_.getNumSubscribers() > 0;
  }

  // Lazy subscription (depth_image_proc's idiom): inputs follow the presence of output subscribers.
  void connectCb() {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    const bool wanted = outputsHaveSubscribers();
    if (wanted && !subscribed_) {
      subscribeInputs();
    } else if (!wanted && subscribed_) {
      points_sub_.unsubscribe();
      image_sub_.unsubscribe();
      compressed_sub_.unsubscribe();
      info_sub_.unsubscribe();
    }
    subscribed_ = wanted;
    diagnostics_.setSubscribed(wanted);
  }

  void subscribeInputs() {
    ros::NodeHandle& nh = getNodeHandle();
    // One message per topic waits for the frame callback (the newest wins): when a frame takes
    // longer than the input period, stale inputs are dropped instead of delaying every later frame.
    // Pairing slack lives in the synchronizer's own queue (queue_size).
    const uint32_t queue = 1;
    points_sub_.subscribe(nh, "points", queue);
    info_sub_.subscribe(nh, "camera_info", queue);
    if (compressed_input_) {
      compressed_sub_.subscribe(nh, "image/compressed", queue);
    } else {
      image_transport::TransportHints hints("raw", ros::TransportHints(), getPrivateNodeHandle());
      image_sub_.subscribe(*it_, "image", queue, hints);
    }
  }

  /// Every message, before the synchronizer sees it: counted, and the clock watched.
  void watchInput(FrameInput input) {
    diagnostics_.countInput(input);
    ros::Duration jump;
    if (!timeline_.clockJumpedBack(ros::Time::now(), &jump)) return;
    NODELET_WARN_THROTTLE(2.0,
                          "time jumped back by %.3f s (bag restarted with --clock?): clearing the "
                          "synchronizer, the tf buffer and the stamp history",
                          jump.toSec());
    // The previous run's messages must not pair with the new ones.
    sync_->restart();
    startOver();
  }

  /// Forgets what came before a restart of the input stream. The tf listener clears its buffer too,
  /// but only when the next tf message arrives, and a lookup before that would interpolate in the
  /// previous run's transforms.
  void startOver() {
    diagnostics_.countTimeJump();
    tf_buffer_->clear();  // keeps /tf_static: tf2's static caches ignore clear()
  }

  /// One synchronized set (raw or compressed image) through the core, to the outputs.
  template <class ImageMsg>
  void onFrame(const typename FrameSynchronizer<ImageMsg>::PointsEvent& points,
               const typename FrameSynchronizer<ImageMsg>::ImageEvent& image_event,
               const typename FrameSynchronizer<ImageMsg>::InfoEvent& info_event) {
    diagnostics_.countSet();
    const ros::Time receipt = latestReceipt(points, image_event, info_event);
    const sensor_msgs::PointCloud2& cloud = *points.getConstMessage();
    const sensor_msgs::CameraInfo& info = *info_event.getConstMessage();
    rc::FrameImage image;  // may refer to the image message, which outlives the frame
    if (!accept(rc::frameImage(*image_event.getConstMessage(), image),
                compressed_input_ ? "image/compressed" : "image")) {
      return;
    }
    const DepthCompletionSettings settings = settings_.get();
    const InputTimeline::Admission admission = timeline_.admit(image.header.stamp);
    if (admission.restarted) {
      NODELET_WARN_THROTTLE(2.0,
                            "input stamps went back by %.3f s (stream restarted?): starting over",
                            admission.back.toSec());
      startOver();
    }
    if (!accept(admission.status, "image")) return;
    const rc::DepthFrameResult frame =
        rc::completeDepthFrame(cloud, image, info, *tf_buffer_, cloud_to_camera_, ground_from_tf_,
                               settings, max_points_, workspace_);
    if (frame.reading.step > 1) {
      diagnostics_.countSubsampled(frame.reading.step);
      NODELET_WARN_THROTTLE(5.0,
                            "cloud of %zu points read every %zu-th point (max_points %zu): set "
                            "max_points, or max_neighbors for dense input, to change this",
                            std::size_t(cloud.width) * cloud.height, frame.reading.step,
                            frame.reading.cap);
    }
    if (!frame.error.empty())
      NODELET_ERROR_THROTTLE(5.0, "depth completion failed: %s", frame.error.c_str());
    if (!accept(frame.status, frame.input) || !frame.completed()) return;
    publishOutputs(workspace_.depth(), settings, image, info, frame.intrinsics, receipt);
  }

  void publishOutputs(const DepthMap& depth, const DepthCompletionSettings& settings,
                      const rc::FrameImage& frame, const sensor_msgs::CameraInfo& info,
                      const PinholeIntrinsics& intrinsics, const ros::Time& receipt) {
    const std_msgs::Header& header = frame.header;
    // The output's recycled message, filled by `convert` (rc::depthImage, varianceImage,
    // maskImage).
    const auto image = [&](RecycledMessage<sensor_msgs::Image>& recycled, const auto& convert) {
      const sensor_msgs::ImagePtr message = recycled.next();
      convert(depth, header, *message);
      return message;
    };
    if (depth_pub_.getNumSubscribers() > 0) {
      sensor_msgs::CameraInfoPtr grid_info = rc::gridCameraInfo(info, depth.grid);
      grid_info->header = header;
      depth_pub_.publish(image(depth_msg_, rc::depthImage), grid_info);
    }
    if (variance_pub_.getNumSubscribers() > 0)
      variance_pub_.publish(image(variance_msg_, rc::varianceImage));
    if (mask_pub_.getNumSubscribers() > 0) mask_pub_.publish(image(mask_msg_, rc::maskImage));
    // Each colour image is computed only while it has a subscriber.
    const auto coloured = [&](RecycledMessage<sensor_msgs::Image>& recycled, const auto& convert,
                              const ColorScale& scale) {
      const sensor_msgs::ImagePtr message = recycled.next();
      convert(depth, scale, header, *message);
      return message;
    };
    if (depth_color_pub_.getNumSubscribers() > 0)
      depth_color_pub_.publish(coloured(depth_color_msg_, rc::depthColorImage, depth_scale_));
    if (stddev_color_pub_.getNumSubscribers() > 0)
      stddev_color_pub_.publish(coloured(stddev_color_msg_, rc::stddevColorImage, stddev_scale_));
    cv::Mat rgb;
    if (points_pub_.getNumSubscribers() > 0 && accept(frame.rgb(rgb), "image")) {
      const sensor_msgs::PointCloud2Ptr cloud = points_msg_.next();
      // On the completer's pool, idle once the scan is complete (this callback is its only user).
      rc::coloredCloud(depth, intrinsics, rgb, settings.cloud_stride, header, *cloud,
                       workspace_.pool());
      points_pub_.publish(cloud);
    }
    const double latency_ms = (ros::Time::now() - receipt).toSec() * 1e3;
    diagnostics_.countPublished(latency_ms, depth.stats);
    adviseOnGroundParameters(depth.stats, settings.params.model);
    if (stats_pub_.getNumSubscribers() > 0) {
      stats_pub_.publish(rc::statsMessage(depth.stats, header, latency_ms));
    }
    if (ground_plane_pub_.getNumSubscribers() > 0) {
      if (const auto polygon = rc::groundPlanePolygon(depth.stats, header))
        ground_plane_pub_.publish(polygon);
    }
  }

  /// Once per node: a ground plane from the parameters is a vehicle's constants (config/radar.yaml
  /// holds View-of-Delft's camera), which silently misplace the road on another vehicle.
  void adviseOnGroundParameters(const DepthMapStats& stats, DepthModel model) {
    if (advised_ground_parameters_ || stats.ground_source != "parameters") return;
    advised_ground_parameters_ = true;
    NODELET_WARN(
        "%s: the ground plane comes from the parameters: the camera %.2f m above the road, "
        "looking %.1f deg above it (ground_camera_height, ground_pitch_deg; config/radar.yaml's "
        "are View-of-Delft's camera). If they are not your camera's, set ground_frame to a z-up "
        "frame whose z = 0 is the road (REP 120 base_footprint) or set both. Shown once; "
        "depth/stats and the diagnostics report the plane of every frame.",
        toString(model), stats.ground_camera_height, stats.ground_pitch_deg);
  }

  /// Counts and logs a rejected input, throttled per reason (one recurring fault must not hide
  /// another); true when `status` is ok.
  bool accept(const rc::ConversionStatus& status, const char* topic) {
    if (status.ok()) return true;
    diagnostics_.countFault(status.fault);
    if (log_throttle_.due(status.fault)) {
      NODELET_ERROR("dropping input set: %s: %s [%s]", topic, status.reason.c_str(),
                    rc::toString(status.fault));
    }
    return false;
  }

  void reconfigure(Config& config, uint32_t /*level*/) {
    if (const auto error =
            settings_.reconfigure(config, settingsFromConfig, writeSettingsToConfig)) {
      NODELET_ERROR("rejected parameter update (%s); keeping the previous values", error->c_str());
    }
  }

  // Static parameters (read once in onInit).
  SyncSettings sync_settings_;
  bool compressed_input_ = false;
  bool advised_ground_parameters_ = false;  // frame callback only
  rc::CloudToCamera cloud_to_camera_;
  rc::GroundFromTf ground_from_tf_;
  int max_points_ = 0;  // < 0: no limit, 0: automatic (pointCap), > 0: that many
  static constexpr double kDefaultDepthColorMax = 50.0;   // m: radar range of View-of-Delft
  static constexpr double kDefaultStddevColorMax = 10.0;  // m
  ColorScale depth_scale_{0.0, kDefaultDepthColorMax, cv::COLORMAP_TURBO};
  ColorScale stddev_scale_{0.0, kDefaultStddevColorMax, cv::COLORMAP_VIRIDIS};

  // Inputs, subscribed only while an output has a subscriber. The synchronizer of the configured
  // image transport is declared after them: it disconnects from them when destroyed.
  std::unique_ptr<image_transport::ImageTransport> it_;
  message_filters::Subscriber<sensor_msgs::PointCloud2> points_sub_;
  image_transport::SubscriberFilter image_sub_;
  message_filters::Subscriber<sensor_msgs::CompressedImage> compressed_sub_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_sub_;
  std::unique_ptr<RestartableSynchronizer> sync_;

  // Outputs. connect_mutex_ also guards their assignment: connect callbacks may fire meanwhile.
  std::mutex connect_mutex_;
  bool subscribed_ = false;
  image_transport::CameraPublisher depth_pub_;
  image_transport::Publisher variance_pub_, mask_pub_, depth_color_pub_, stddev_color_pub_;
  ros::Publisher points_pub_, stats_pub_, ground_plane_pub_;
  // Output messages written again once their subscribers are done with them (frame callback only).
  RecycledMessage<sensor_msgs::Image> depth_msg_, variance_msg_, mask_msg_, depth_color_msg_,
      stddev_color_msg_;
  RecycledMessage<sensor_msgs::PointCloud2> points_msg_;

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;

  // Written by the reconfigure callback, copied once per frame by the frame callback.
  GuardedSettings<DepthCompletionSettings> settings_;
  std::unique_ptr<dynamic_reconfigure::Server<Config>> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;

  // Input and frame callbacks' state (one at a time: the nodelet's callback queue is
  // single-threaded).
  DepthCompletionWorkspace workspace_;
  InputTimeline timeline_;
  DepthCompletionDiagnostics diagnostics_;
  PerFaultLogThrottle<rc::kInputFaultCount> log_throttle_;
};

}  // namespace multimodal_nvs

PLUGINLIB_EXPORT_CLASS(multimodal_nvs::DepthCompletionNodelet, nodelet::Nodelet)
