#pragma once
// Pairs a PointCloud2, an image (raw Image or CompressedImage) and a CameraInfo by header stamp,
// with the exact or the approximate message_filters policy chosen at run time.
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <ros/message_event.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/PointCloud2.h>
#include <boost/function.hpp>
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

}  // namespace multimodal_nvs
