#pragma once
// The conditioning renderer nodelet's output topics: advertised together, published per frame only
// where someone listens (the preview, the costly one, is computed only then).
#include <image_transport/camera_publisher.h>
#include <image_transport/image_transport.h>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"

namespace multimodal_nvs {

class ConditioningRendererOutputs {
 public:
  /// conditioning/{image, camera_info, mask, depth, preview}; the callbacks run when a subscriber
  /// of any of them comes or goes. Pass plain boost::bind objects (see the .cpp).
  void advertise(image_transport::ImageTransport& it, uint32_t queue_size,
                 const image_transport::SubscriberStatusCallback& image_cb,
                 const ros::SubscriberStatusCallback& info_cb);
  bool anySubscribed() const;
  void publish(const RenderedFrame& frame, const PinholeIntrinsics& intrinsics,
               const ImageSize& size, const std_msgs::Header& header);

 private:
  image_transport::CameraPublisher image_;  // conditioning/image + conditioning/camera_info
  image_transport::Publisher mask_, depth_, preview_;
};

}  // namespace multimodal_nvs
