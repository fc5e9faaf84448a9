#pragma once
// Pairs a PointCloud2, an image (raw Image or CompressedImage) and a CameraInfo by header stamp,
// with the exact or the approximate message_filters policy chosen at run time, and restartable.
#include <message_filters/pass_through.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <ros/message_event.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/PointCloud2.h>
#include <algorithm>
#include <array>
#include <boost/function.hpp>
#include <functional>
#include <memory>

namespace multimodal_nvs {

struct SyncSettings {
  int queue_size = 5;
  /// ApproximateTime (default) pairs messages whose stamps differ; ExactTime needs equal stamps.
  bool approximate = true;
  /// ApproximateTime only: sets whose stamps span more than this (s) are never formed; 0 = no
  /// limit.
  double max_interval = 0.0;
};

/// One synchronizer over (points, ImageMsg, camera_info). The callback receives message events so
/// that it can read each message's receipt time (latency is measured from the latest of them).
template <class ImageMsg>
class FrameSynchronizer {
 public:
  using PointsEvent = ros::MessageEvent<const sensor_msgs::PointCloud2>;
  using ImageEvent = ros::MessageEvent<const ImageMsg>;
  using InfoEvent = ros::MessageEvent<const sensor_msgs::CameraInfo>;
  using Callback = boost::function<void(const PointsEvent&, const ImageEvent&, const InfoEvent&)>;

  template <class PointsFilter, class ImageFilter, class InfoFilter>
  FrameSynchronizer(const SyncSettings& settings, PointsFilter& points, ImageFilter& image,
                    InfoFilter& info, const Callback& callback) {
    // message_filters hands events to a callback only through its nine-argument form.
    using NullP = const boost::shared_ptr<const message_filters::NullType>&;
    const boost::function<void(const PointsEvent&, const ImageEvent&, const InfoEvent&, NullP,
                               NullP, NullP, NullP, NullP, NullP)>
        adapter = [callback](const PointsEvent& p, const ImageEvent& i, const InfoEvent& c, NullP,
                             NullP, NullP, NullP, NullP, NullP) { callback(p, i, c); };
    if (settings.approximate) {
      ApproximatePolicy policy(settings.queue_size);
      if (settings.max_interval > 0.0) {
        policy.setMaxIntervalDuration(ros::Duration(settings.max_interval));
      }
      // const: a non-const policy would bind to the four-filter constructor.
      const ApproximatePolicy& const_policy = policy;
      approximate_.reset(
          new message_filters::Synchronizer<ApproximatePolicy>(const_policy, points, image, info));
      approximate_->registerCallback(adapter);
    } else {
      const ExactPolicy policy(settings.queue_size);
      exact_.reset(new message_filters::Synchronizer<ExactPolicy>(policy, points, image, info));
      exact_->registerCallback(adapter);
    }
  }

 private:
  using ApproximatePolicy =
      message_filters::sync_policies::ApproximateTime<sensor_msgs::PointCloud2, ImageMsg,
                                                      sensor_msgs::CameraInfo>;
  using ExactPolicy = message_filters::sync_policies::ExactTime<sensor_msgs::PointCloud2, ImageMsg,
                                                                sensor_msgs::CameraInfo>;
  std::unique_ptr<message_filters::Synchronizer<ApproximatePolicy>> approximate_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
};

/// When the last message of a synchronized set arrived: a node's latency starts there.
template <class PointsEvent, class ImageEvent, class InfoEvent>
ros::Time latestReceipt(const PointsEvent& points, const ImageEvent& image, const InfoEvent& info) {
  return std::max({points.getReceiptTime(), image.getReceiptTime(), info.getReceiptTime()});
}

/// The three inputs of a FrameSynchronizer.
enum class FrameInput { kPoints, kImage, kCameraInfo };

/// What a node holds of a RestartableFrameSynchronizer, whichever its image message.
class RestartableSynchronizer {
 public:
  virtual ~RestartableSynchronizer() = default;
  /// Drops every queued message: the next set is formed from messages received from now on.
  virtual void restart() = 0;
};

/// A FrameSynchronizer behind one gate per input. Every message is first shown to `watch` (which
/// counts it and may call restart()), then passed on. restart() replaces the synchronizer and its
/// queues with it, so that after a restarted stream (a bag played again) the previous run's
/// messages never pair with the new ones. Safe from inside `watch`: the synchronizer is connected
/// to the gates, whose signals are not being called yet. The sources must outlive this object.
template <class ImageMsg>
class RestartableFrameSynchronizer : public RestartableSynchronizer {
 public:
  using Sync = FrameSynchronizer<ImageMsg>;
  using Watch = std::function<void(FrameInput)>;

  template <class PointsSource, class ImageSource, class InfoSource>
  RestartableFrameSynchronizer(const SyncSettings& settings, PointsSource& points,
                               ImageSource& image, InfoSource& info, Watch watch,
                               typename Sync::Callback callback)
      : settings_(settings), watch_(std::move(watch)), callback_(std::move(callback)) {
    restart();
    connections_[0] = connect(points, points_gate_, FrameInput::kPoints);
    connections_[1] = connect(image, image_gate_, FrameInput::kImage);
    connections_[2] = connect(info, info_gate_, FrameInput::kCameraInfo);
  }

  ~RestartableFrameSynchronizer() override {
    for (message_filters::Connection& connection : connections_)
      connection.disconnect();
  }

  RestartableFrameSynchronizer(const RestartableFrameSynchronizer&) = delete;
  RestartableFrameSynchronizer& operator=(const RestartableFrameSynchronizer&) = delete;

  void restart() override {
    sync_.reset();
    sync_ = std::make_unique<Sync>(settings_, points_gate_, image_gate_, info_gate_, callback_);
  }

 private:
  template <class Source, class M>
  message_filters::Connection connect(Source& source, message_filters::PassThrough<M>& gate,
                                      FrameInput input) {
    const boost::function<void(const ros::MessageEvent<const M>&)> forward =
        [this, &gate, input](const ros::MessageEvent<const M>& event) {
          watch_(input);
          gate.add(event);
        };
    return source.registerCallback(forward);
  }

  SyncSettings settings_;
  Watch watch_;
  typename Sync::Callback callback_;
  message_filters::PassThrough<sensor_msgs::PointCloud2> points_gate_;
  message_filters::PassThrough<ImageMsg> image_gate_;
  message_filters::PassThrough<sensor_msgs::CameraInfo> info_gate_;
  std::unique_ptr<Sync> sync_;
  std::array<message_filters::Connection, 3> connections_;
};

}  // namespace multimodal_nvs
