// multimodal_nvs/DepthCompletion: synchronized PointCloud2 + Image + CameraInfo in; REP-118 depth,
// variance, mask, coloured cloud and stats out. Wiring only: conversions live in
// multimodal_nvs/ros/conversions.hpp and the algorithm in the core's DepthCompleter.
#include <dynamic_reconfigure/server.h>
#include <image_transport/camera_publisher.h>
#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/pass_through.h>
#include <message_filters/subscriber.h>
#include <nodelet/nodelet.h>
#include <sensor_msgs/CompressedImage.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <boost/make_shared.hpp>
#include <pluginlib/class_list_macros.hpp>

#include <array>
#include <functional>
#include <memory>
#include <mutex>
#include <new>

#include "depth_completion_diagnostics.hpp"
// The generated depth/stats message shares its name with the core's multimodal_nvs::
// DepthCompletionStats, so it is built in depth_completion_stats.cpp, out of this file's sight.
#include "depth_completion_stats.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/ros/conversions.hpp"
#include "multimodal_nvs/ros/depth_completion_config.hpp"
#include "multimodal_nvs/ros/frame_synchronizer.hpp"
#include "multimodal_nvs/ros/input_timeline.hpp"
#include "multimodal_nvs/ros/recycled_message.hpp"
#include "nodelet_state.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

class DepthCompletionNodelet : public nodelet::Nodelet {
 private:
  using Config = DepthCompletionConfig;
  using RawSync = FrameSynchronizer<sensor_msgs::Image>;
  using CompressedSync = FrameSynchronizer<sensor_msgs::CompressedImage>;
  /// Produces the full-size RGB image on demand: only depth/points needs colour.
  using ColourSource = std::function<rc::ConversionStatus(cv::Mat&)>;

  void onInit() override;
  void advertiseOutputs();
  void connectCb();
  bool outputsHaveSubscribers() const;
  void subscribeInputs();
  template <class M>
  void gate(message_filters::SimpleFilter<M>& subscriber, message_filters::PassThrough<M>& gate,
            DepthCompletionDiagnostics::Input input);
  void createSynchronizer();
  void startOver();
  bool acceptStamp(const ros::Time& stamp);
  std::size_t pointCap(const DepthCompletionSettings& settings) const;
  template <class PointsEvent, class ImageEvent, class InfoEvent>
  ros::Time countSet(const PointsEvent& points, const ImageEvent& image, const InfoEvent& info);
  void onRawFrame(const RawSync::PointsEvent& points, const RawSync::ImageEvent& image,
                  const RawSync::InfoEvent& info);
  void onCompressedFrame(const CompressedSync::PointsEvent& points,
                         const CompressedSync::ImageEvent& image,
                         const CompressedSync::InfoEvent& info);
  void processFrame(const sensor_msgs::PointCloud2& cloud, const std_msgs::Header& image_header,
                    const ImageSize& image_size, const ColourSource& colour,
                    const sensor_msgs::CameraInfo& info, const ros::Time& receipt);
  void publishOutputs(const DepthMap& depth, const DepthCompletionSettings& settings,
                      const std_msgs::Header& header, const sensor_msgs::CameraInfo& info,
                      const PinholeIntrinsics& intrinsics, const ColourSource& colour,
                      const ros::Time& receipt);
  bool lookupSensorToCamera(const std_msgs::Header& cloud_header, const std::string& camera_frame,
                            Eigen::Isometry3d& sensor_to_camera);
  bool accept(const rc::ConversionStatus& status, const char* topic);
  void releaseOversizedBuffers();
  void reconfigure(Config& config, uint32_t level);

  // Static parameters (read once in onInit).
  SyncSettings sync_settings_;
  bool compressed_input_ = false;
  ros::Duration tf_timeout_;
  int max_points_ = 0;  // < 0: no limit, 0: automatic (pointCap), > 0: that many

  // Inputs, subscribed only while an output has a subscriber.
  std::unique_ptr<image_transport::ImageTransport> it_;
  message_filters::Subscriber<sensor_msgs::PointCloud2> points_sub_;
  image_transport::SubscriberFilter image_sub_;
  message_filters::Subscriber<sensor_msgs::CompressedImage> compressed_sub_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_sub_;
  // Every message passes a gate that watches the clock before the synchronizer sees it: after a
  // backward jump the gate replaces the synchronizer, and its queues with it.
  message_filters::PassThrough<sensor_msgs::PointCloud2> points_gate_;
  message_filters::PassThrough<sensor_msgs::Image> image_gate_;
  message_filters::PassThrough<sensor_msgs::CompressedImage> compressed_gate_;
  message_filters::PassThrough<sensor_msgs::CameraInfo> info_gate_;
  std::unique_ptr<RawSync> raw_sync_;
  std::unique_ptr<CompressedSync> compressed_sync_;

  // Outputs. connect_mutex_ also guards their assignment: connect callbacks may fire meanwhile.
  std::mutex connect_mutex_;
  bool subscribed_ = false;
  image_transport::CameraPublisher depth_pub_;
  image_transport::Publisher variance_pub_, mask_pub_;
  ros::Publisher points_pub_, stats_pub_;
  // Output messages written again once their subscribers are done with them (frame callback only).
  RecycledMessage<sensor_msgs::Image> depth_msg_, variance_msg_, mask_msg_;
  RecycledMessage<sensor_msgs::PointCloud2> points_msg_;

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;

  // Written by the reconfigure callback, copied once per frame by the frame callback.
  GuardedSettings<DepthCompletionSettings> settings_;
  std::unique_ptr<dynamic_reconfigure::Server<Config>> reconfigure_server_;
  boost::recursive_mutex reconfigure_mutex_;

  // Frame-callback state (one frame at a time: the nodelet's callback queue is single-threaded).
  ThreadCountCached<DepthCompleter> completer_;
  std::vector<Eigen::Vector3d> points_camera_;
  // Reused every frame: fresh full-resolution buffers cost page faults on every scan (21 MB at
  // 1936x1216); the published messages are separate copies.
  DepthMap depth_;
  DepthCompletionDiagnostics diagnostics_;
  // Time bookkeeping (input and frame callbacks, one at a time as above).
  ClockWatch clock_watch_;
  StampOrder stamp_order_;
  PerFaultLogThrottle<rc::kInputFaultCount> log_throttle_;
};

void DepthCompletionNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  sync_settings_.queue_size = pnh.param("queue_size", 5);
  sync_settings_.approximate = pnh.param("approximate_sync", true);
  sync_settings_.max_interval = pnh.param("max_interval", 0.0);
  compressed_input_ = pnh.param("compressed_input", false);
  tf_timeout_ = ros::Duration(pnh.param("tf_timeout", 0.1));
  max_points_ = pnh.param("max_points", 0);

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  diagnostics_.start(nh, pnh, getName());

  // The .cfg defaults first, then whatever the parameter server (YAML) holds, through one mapping.
  settings_.set(settingsFromConfig(Config::__getDefault__()));
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<Config>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(boost::bind(&DepthCompletionNodelet::reconfigure, this,
                                               boost::placeholders::_1, boost::placeholders::_2));

  it_ = std::make_unique<image_transport::ImageTransport>(nh);
  createSynchronizer();
  using Input = DepthCompletionDiagnostics::Input;
  gate(points_sub_, points_gate_, Input::kPoints);
  gate(image_sub_, image_gate_, Input::kImage);
  gate(compressed_sub_, compressed_gate_, Input::kImage);
  gate(info_sub_, info_gate_, Input::kCameraInfo);
  advertiseOutputs();
}

void DepthCompletionNodelet::advertiseOutputs() {
  ros::NodeHandle& nh = getNodeHandle();
  image_transport::SubscriberStatusCallback image_cb =
      boost::bind(&DepthCompletionNodelet::connectCb, this);
  ros::SubscriberStatusCallback topic_cb = boost::bind(&DepthCompletionNodelet::connectCb, this);
  std::lock_guard<std::mutex> lock(connect_mutex_);
  depth_pub_ = it_->advertiseCamera("depth/image", 1, image_cb, image_cb, topic_cb, topic_cb);
  variance_pub_ = it_->advertise("depth/variance", 1, image_cb, image_cb);
  mask_pub_ = it_->advertise("depth/mask", 1, image_cb, image_cb);
  points_pub_ = nh.advertise<sensor_msgs::PointCloud2>("depth/points", 1, topic_cb, topic_cb);
  stats_pub_ = advertiseStats(nh, "depth/stats", topic_cb);
}

bool DepthCompletionNodelet::outputsHaveSubscribers() const {
  return depth_pub_.getNumSubscribers() > 0 || variance_pub_.getNumSubscribers() > 0 ||
         mask_pub_.getNumSubscribers() > 0 || points_pub_.getNumSubscribers() > 0 ||
         stats_pub_.getNumSubscribers() > 0;
}

// Lazy subscription (depth_image_proc's idiom): inputs follow the presence of output subscribers.
void DepthCompletionNodelet::connectCb() {
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

void DepthCompletionNodelet::subscribeInputs() {
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

/// Passes every message of `subscriber` through `gate` to the synchronizer, counting it and
/// watching the clock first. Replacing the synchronizer here is safe: it is connected to the gates,
/// whose signals are not being called yet.
template <class M>
void DepthCompletionNodelet::gate(message_filters::SimpleFilter<M>& subscriber,
                                  message_filters::PassThrough<M>& gate,
                                  DepthCompletionDiagnostics::Input input) {
  const boost::function<void(const ros::MessageEvent<const M>&)> callback =
      [this, &gate, input](const ros::MessageEvent<const M>& event) {
        diagnostics_.countInput(input);
        ros::Duration jump;
        if (clock_watch_.jumpedBack(ros::Time::now(), &jump)) {
          NODELET_WARN_THROTTLE(2.0,
                                "time jumped back by %.3f s (bag restarted with --clock?): "
                                "clearing the synchronizer, the tf buffer and the stamp history",
                                jump.toSec());
          createSynchronizer();  // the previous run's messages must not pair with the new ones
          startOver();
        }
        gate.add(event);
      };
  subscriber.registerCallback(callback);
}

void DepthCompletionNodelet::createSynchronizer() {
  raw_sync_.reset();
  compressed_sync_.reset();
  if (compressed_input_) {
    compressed_sync_ = std::make_unique<CompressedSync>(
        sync_settings_, points_gate_, compressed_gate_, info_gate_,
        boost::bind(&DepthCompletionNodelet::onCompressedFrame, this, boost::placeholders::_1,
                    boost::placeholders::_2, boost::placeholders::_3));
  } else {
    raw_sync_ = std::make_unique<RawSync>(
        sync_settings_, points_gate_, image_gate_, info_gate_,
        boost::bind(&DepthCompletionNodelet::onRawFrame, this, boost::placeholders::_1,
                    boost::placeholders::_2, boost::placeholders::_3));
  }
}

/// Forgets what came before a restart of the input stream. The tf listener clears its buffer too,
/// but only when the next tf message arrives, and a lookup before that would interpolate in the
/// previous run's transforms.
void DepthCompletionNodelet::startOver() {
  diagnostics_.countTimeJump();
  tf_buffer_->clear();  // keeps /tf_static: tf2's static caches ignore clear()
  stamp_order_.reset();
}

/// Drops a set whose image stamp repeats or precedes the last processed one; a stamp far in the
/// past is a restarted stream (a bag replayed without --clock) and starts over.
bool DepthCompletionNodelet::acceptStamp(const ros::Time& stamp) {
  const ros::Time last = stamp_order_.last();
  switch (stamp_order_.check(stamp)) {
    case StampOrder::Verdict::kNewer:
      return true;
    case StampOrder::Verdict::kRestart:
      NODELET_WARN_THROTTLE(2.0,
                            "input stamps went back by %.3f s (stream restarted?): starting over",
                            (last - stamp).toSec());
      startOver();
      stamp_order_.check(stamp);
      return true;
    case StampOrder::Verdict::kNotNewer:
      break;
  }
  return accept(rc::ConversionStatus::failure(rc::InputFault::kStampNotNewer,
                                              "image stamp " + std::to_string(stamp.toSec()) +
                                                  (stamp == last ? " repeats" : " precedes") +
                                                  " the last processed set's " +
                                                  std::to_string(last.toSec())),
                "image");
}

/// Most points the model is given per set. The exact reference GP (local_gp_mle without
/// max_neighbors) solves one GP per distinct neighbour set, and both the sets' number and size grow
/// with the density: on a 320x240 image 10k points take 13 s on one core and 30k points more than
/// 2 minutes and 2.7 GB. The other models are linear in the points (200k: ~4 s for ground_gp).
std::size_t DepthCompletionNodelet::pointCap(const DepthCompletionSettings& settings) const {
  if (max_points_ < 0) return 0;
  if (max_points_ > 0) return std::size_t(max_points_);
  const bool exact_gp =
      settings.params.model == DepthModel::kLocalGpMle && settings.params.max_neighbors == 0;
  return exact_gp ? 5000 : 200000;
}

/// Counts a synchronized set; returns when its last message arrived (the latency's start).
template <class PointsEvent, class ImageEvent, class InfoEvent>
ros::Time DepthCompletionNodelet::countSet(const PointsEvent& points, const ImageEvent& image,
                                           const InfoEvent& info) {
  diagnostics_.countInput(DepthCompletionDiagnostics::Input::kSet);
  return std::max({points.getReceiptTime(), image.getReceiptTime(), info.getReceiptTime()});
}

void DepthCompletionNodelet::onRawFrame(const RawSync::PointsEvent& points,
                                        const RawSync::ImageEvent& image,
                                        const RawSync::InfoEvent& info) {
  const ros::Time receipt = countSet(points, image, info);
  const sensor_msgs::Image& msg = *image.getConstMessage();
  if (!accept(rc::validateImage(msg), "image")) return;
  // rgb8 is wrapped without a copy; `msg` outlives the frame.
  const ColourSource colour = [&msg](cv::Mat& rgb) { return rc::rgbFromImage(msg, rgb); };
  processFrame(*points.getConstMessage(), msg.header, ImageSize{int(msg.height), int(msg.width)},
               colour, *info.getConstMessage(), receipt);
}

void DepthCompletionNodelet::onCompressedFrame(const CompressedSync::PointsEvent& points,
                                               const CompressedSync::ImageEvent& image,
                                               const CompressedSync::InfoEvent& info) {
  const ros::Time receipt = countSet(points, image, info);
  // Decoding is the only way to learn the image size, so it happens for every synced set.
  cv::Mat rgb;
  if (!accept(rc::rgbFromCompressed(*image.getConstMessage(), rgb), "image/compressed")) return;
  const ColourSource colour = [&rgb](cv::Mat& out) {
    out = rgb;
    return rc::ConversionStatus::success();
  };
  processFrame(*points.getConstMessage(), image.getConstMessage()->header,
               ImageSize{rgb.rows, rgb.cols}, colour, *info.getConstMessage(), receipt);
}

void DepthCompletionNodelet::processFrame(const sensor_msgs::PointCloud2& cloud,
                                          const std_msgs::Header& image_header,
                                          const ImageSize& image_size, const ColourSource& colour,
                                          const sensor_msgs::CameraInfo& info,
                                          const ros::Time& receipt) {
  const DepthCompletionSettings settings = settings_.get();
  if (!acceptStamp(image_header.stamp)) return;
  PinholeIntrinsics intrinsics;
  if (!accept(rc::intrinsicsFromCameraInfo(info, image_size, intrinsics), "camera_info")) return;
  // Layout first, so that a malformed cloud is reported as such and not as a missing transform.
  if (!accept(rc::validateCloudLayout(cloud), "points")) return;
  Eigen::Isometry3d sensor_to_camera;
  if (!lookupSensorToCamera(cloud.header, image_header.frame_id, sensor_to_camera)) return;
  std::size_t non_finite = 0, step = 1;
  const std::size_t cap = pointCap(settings);
  if (!accept(rc::pointsFromCloud(cloud, sensor_to_camera, cap, points_camera_, &non_finite, &step),
              "points") ||
      !accept(rc::checkPointsInFront(points_camera_), "points")) {
    return;
  }
  if (step > 1) {
    diagnostics_.countSubsampled(step);
    NODELET_WARN_THROTTLE(5.0,
                          "cloud of %zu points read every %zu-th point (max_points %zu): set "
                          "max_points, or max_neighbors for dense input, to change this",
                          std::size_t(cloud.width) * cloud.height, step, cap);
  }
  try {
    completer_.forThreads(settings.params.threads)
        .complete(points_camera_, intrinsics, StrideGrid{image_size, settings.stride},
                  settings.params, depth_);
  } catch (const InputError& e) {  // parameters and intrinsics were validated: not expected
    NODELET_ERROR_THROTTLE(5.0, "depth completion failed: %s", e.what());
    return;
  } catch (const std::bad_alloc&) {
    // One allocation too large for this host (the model's buffers grow with points and pixels):
    // the set is lost, the node is not. The thread pool rethrows its workers' exceptions here;
    // max_points keeps the allocations of a dense cloud small in the first place.
    accept(rc::ConversionStatus::failure(
               rc::InputFault::kOutOfMemory,
               "depth completion of " + std::to_string(points_camera_.size()) + " points on a " +
                   std::to_string(image_size.width) + "x" + std::to_string(image_size.height) +
                   " image ran out of memory"),
           "points");
    releaseOversizedBuffers();
    return;
  }
  releaseOversizedBuffers();
  publishOutputs(depth_, settings, image_header, info, intrinsics, colour, receipt);
}

void DepthCompletionNodelet::publishOutputs(const DepthMap& depth,
                                            const DepthCompletionSettings& settings,
                                            const std_msgs::Header& header,
                                            const sensor_msgs::CameraInfo& info,
                                            const PinholeIntrinsics& intrinsics,
                                            const ColourSource& colour, const ros::Time& receipt) {
  // The output's recycled message, filled by `convert` (rc::depthImage, varianceImage, maskImage).
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
  cv::Mat rgb;
  if (points_pub_.getNumSubscribers() > 0 && accept(colour(rgb), "image")) {
    const sensor_msgs::PointCloud2Ptr cloud = points_msg_.next();
    rc::coloredCloud(depth, intrinsics, rgb, settings.cloud_stride, header, *cloud);
    points_pub_.publish(cloud);
  }
  const double latency_ms = (ros::Time::now() - receipt).toSec() * 1e3;
  diagnostics_.countPublished(latency_ms, depth.stats.compute_ms);
  if (stats_pub_.getNumSubscribers() == 0) return;
  publishStats(
      stats_pub_, header,
      FrameStatsFields{unsigned(depth.stats.points_total), unsigned(depth.stats.points_in_view),
                       unsigned(depth.stats.neighbour_sets), unsigned(depth.stats.kept),
                       depth.stats.compute_ms, latency_ms});
}

bool DepthCompletionNodelet::lookupSensorToCamera(const std_msgs::Header& cloud_header,
                                                  const std::string& camera_frame,
                                                  Eigen::Isometry3d& sensor_to_camera) {
  if (cloud_header.frame_id == camera_frame) {
    sensor_to_camera.setIdentity();
    return true;
  }
  try {
    sensor_to_camera = tf2::transformToEigen(tf_buffer_->lookupTransform(
        camera_frame, cloud_header.frame_id, cloud_header.stamp, tf_timeout_));
    return true;
  } catch (const tf2::TransformException& e) {
    return accept(rc::ConversionStatus::failure(rc::InputFault::kTransformUnavailable, e.what()),
                  "tf");
  }
}

/// Counts and logs a rejected input, throttled per reason (one recurring fault must not hide
/// another); true when `status` is ok.
bool DepthCompletionNodelet::accept(const rc::ConversionStatus& status, const char* topic) {
  if (status.ok()) return true;
  diagnostics_.countFault(status.fault);
  if (log_throttle_.due(status.fault)) {
    NODELET_ERROR("dropping input set: %s: %s [%s]", topic, status.reason.c_str(),
                  rc::toString(status.fault));
  }
  return false;
}

/// One huge cloud must not pin its buffer for the rest of the run.
void DepthCompletionNodelet::releaseOversizedBuffers() {
  // After one huge input (10 million points, an 8000x8000 image) the buffers shrink back, so that
  // memory stays bounded by the usual input, not by the largest one seen.
  const auto oversized = [](const auto& buffer) {
    return buffer.capacity() > 4 * buffer.size() + (1u << 16);
  };
  if (oversized(points_camera_)) std::vector<Eigen::Vector3d>().swap(points_camera_);
  if (oversized(depth_.depth) || oversized(depth_.variance) || oversized(depth_.valid)) {
    depth_ = DepthMap{};
  }
}

void DepthCompletionNodelet::reconfigure(Config& config, uint32_t /*level*/) {
  if (const auto error = settings_.reconfigure(config, settingsFromConfig, writeSettingsToConfig)) {
    NODELET_ERROR("rejected parameter update (%s); keeping the previous values", error->c_str());
  }
}

}  // namespace multimodal_nvs

PLUGINLIB_EXPORT_CLASS(multimodal_nvs::DepthCompletionNodelet, nodelet::Nodelet)
