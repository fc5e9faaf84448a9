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
#include <string>

#include "multimodal_nvs/ros/input_period_bound.hpp"

namespace multimodal_nvs {

struct SyncSettings {
  int queue_size = 5;
  /// ApproximateTime (default) pairs messages whose stamps differ; ExactTime needs equal stamps.
  bool approximate = true;
  /// ApproximateTime only: sets whose stamps span more than this (s) are never formed; 0 = no
  /// limit.
  double max_interval = 0.0;
  /// ApproximateTime only: how much an earlier set is preferred to a later one whose stamps lie
  /// closer together (message_filters' age penalty; its default). Higher values publish sooner
  /// and may pair a cloud with an image further away in time.
  double age_penalty = 0.1;
  /// ApproximateTime only: each input's inter-message lower bound is this fraction of the shortest
  /// interval between its stamps seen so far (InputPeriodBound); 0 = no bound, every set waits for
  /// a later message to prove it optimal.
  double period_bound_fraction = 0.9;
};

/// The settings' problems as one sentence each (negative or non-finite values, a fraction of 1 or
/// more, which would put the next message later than it can come); empty when they are usable.
std::string syncSettingsProblem(const SyncSettings& settings);

/// The three inputs of a FrameSynchronizer, in the order of its message types.
enum class FrameInput { kPoints, kImage, kCameraInfo };

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
      policy.setAgePenalty(settings.age_penalty);
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

  /// The approximate policy's lower bound (s) on the time between two stamps of `input`; ignored
  /// by the exact policy.
  void setInterMessageLowerBound(FrameInput input, double seconds) {
    if (approximate_) {
      approximate_->setInterMessageLowerBound(static_cast<int>(input), ros::Duration(seconds));
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

/// What a node holds of a RestartableFrameSynchronizer, whichever its image message.
class RestartableSynchronizer {
 public:
  virtual ~RestartableSynchronizer() = default;
  /// Drops every queued message: the next set is formed from messages received from now on.
  virtual void restart() = 0;
};

/// A FrameSynchronizer behind one gate per input. Every message is first shown to `watch` (which
/// counts it and may call restart()), then its stamp to the input's InputPeriodBound (a changed
/// bound goes to the synchronizer, and to every synchronizer restart() makes), then it is passed
/// on. The bounds are changed only here, on the thread that adds messages: a nodelet's inputs
/// arrive on its single-threaded node handle, so no message is being added meanwhile. restart()
/// replaces the synchronizer and its queues with it, so that after a restarted stream (a bag played
/// again) the previous run's messages never pair with the new ones. Safe from inside `watch`: the
/// synchronizer is connected to the gates, whose signals are not being called yet. The sources must
/// outlive this object.
template <class ImageMsg>
class RestartableFrameSynchronizer : public RestartableSynchronizer {
 public:
  using Sync = FrameSynchronizer<ImageMsg>;
  using Watch = std::function<void(FrameInput)>;

  template <class PointsSource, class ImageSource, class InfoSource>
  RestartableFrameSynchronizer(const SyncSettings& settings, PointsSource& points,
                               ImageSource& image, InfoSource& info, Watch watch,
                               typename Sync::Callback callback)
      : settings_(settings),
        watch_(std::move(watch)),
        callback_(std::move(callback)),
        periods_{InputPeriodBound(settings.period_bound_fraction),
                 InputPeriodBound(settings.period_bound_fraction),
                 InputPeriodBound(settings.period_bound_fraction)} {
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
    // The sensors' periods do not change with a restarted stream.
    for (int i = 0; i < 3; ++i) {
      if (periods_[i].bound() > 0.0)
        sync_->setInterMessageLowerBound(static_cast<FrameInput>(i), periods_[i].bound());
    }
  }

 private:
  template <class Source, class M>
  message_filters::Connection connect(Source& source, message_filters::PassThrough<M>& gate,
                                      FrameInput input) {
    const boost::function<void(const ros::MessageEvent<const M>&)> forward =
        [this, &gate, input](const ros::MessageEvent<const M>& event) {
          watch_(input);
          InputPeriodBound& period = periods_[static_cast<int>(input)];
          if (period.observe(event.getMessage()->header.stamp.toSec()))
            sync_->setInterMessageLowerBound(input, period.bound());
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
  std::array<InputPeriodBound, 3> periods_;  // by FrameInput
  std::unique_ptr<Sync> sync_;
  std::array<message_filters::Connection, 3> connections_;
};

}  // namespace multimodal_nvs
