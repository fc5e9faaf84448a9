#pragma once
// The conditioning renderer nodelet's input topics: every camera image (the live view follows
// it), and image, depth/image, depth/mask and depth/camera_info paired by exact time (the
// keyframes), subscribed only while something wants them.
#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/subscriber.h>
#include <message_filters/time_synchronizer.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <boost/function.hpp>
#include <memory>

namespace multimodal_nvs {

class ConditioningRendererInputs {
 public:
  using Callback = boost::function<void(
      const sensor_msgs::ImageConstPtr& image, const sensor_msgs::ImageConstPtr& depth,
      const sensor_msgs::ImageConstPtr& mask, const sensor_msgs::CameraInfoConstPtr& depth_info)>;

  using CameraCallback = boost::function<void(const sensor_msgs::ImageConstPtr& image)>;

  /// `queue_size`: the synchronizer's pairing slack; `on_set` gets every synchronized set,
  /// `on_image` every camera image.
  ConditioningRendererInputs(int queue_size, const Callback& on_set,
                             const CameraCallback& on_image);

  /// The synchronized topics queue `queue_size` messages each (the image of a depth set must still
  /// be there when its depth, seconds later, arrives), the camera `camera_queue_size` images; the
  /// images come raw unless the private `image_transport` parameter says otherwise.
  void subscribe(image_transport::ImageTransport& it, ros::NodeHandle& nh,
                 const ros::NodeHandle& private_nh, uint32_t camera_queue_size);
  void unsubscribe();

 private:
  using Image = sensor_msgs::Image;
  using Sync = message_filters::TimeSynchronizer<Image, Image, Image, sensor_msgs::CameraInfo>;

  image_transport::SubscriberFilter image_, depth_, mask_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_;
  std::unique_ptr<Sync> sync_;
  uint32_t queue_size_;
  CameraCallback on_image_;
  image_transport::Subscriber camera_;
};

}  // namespace multimodal_nvs
