#include "conditioning_renderer_inputs.hpp"

#include <algorithm>
#include <boost/bind/bind.hpp>

namespace multimodal_nvs {

ConditioningRendererInputs::ConditioningRendererInputs(int queue_size, const Callback& on_set,
                                                       const CameraCallback& on_image)
    : sync_(std::make_unique<Sync>(image_, depth_, mask_, info_, queue_size)),
      queue_size_(static_cast<uint32_t>(std::max(1, queue_size))),
      on_image_(on_image) {
  // bind, not on_set itself: the synchronizer calls with nine arguments, the last five NullType.
  sync_->registerCallback(boost::bind(on_set, boost::placeholders::_1, boost::placeholders::_2,
                                      boost::placeholders::_3, boost::placeholders::_4));
}

void ConditioningRendererInputs::subscribe(image_transport::ImageTransport& it, ros::NodeHandle& nh,
                                           const ros::NodeHandle& private_nh,
                                           uint32_t camera_queue_size) {
  image_transport::TransportHints hints("raw", ros::TransportHints(), private_nh);
  camera_ = it.subscribe("image", camera_queue_size, on_image_, ros::VoidPtr(), hints);
  image_.subscribe(it, "image", queue_size_, hints);
  depth_.subscribe(it, "depth/image", queue_size_, hints);
  mask_.subscribe(it, "depth/mask", queue_size_, hints);
  info_.subscribe(nh, "depth/camera_info", queue_size_);
}

void ConditioningRendererInputs::unsubscribe() {
  camera_.shutdown();
  image_.unsubscribe();
  depth_.unsubscribe();
  mask_.unsubscribe();
  info_.unsubscribe();
}

}  // namespace multimodal_nvs
