#include "conditioning_renderer_outputs.hpp"

#include "multimodal_nvs/core/render/preview.hpp"
#include "multimodal_nvs/ros/renderer_conversions.hpp"

namespace multimodal_nvs {

namespace rc = ros_conversions;

// image_transport copies these callbacks into its own binders and may destroy one copy on a
// roscpp thread while another thread still calls another (at shutdown). A boost::bind of a member
// function and `this` sits inside boost::function's buffer and is trivially destroyed; a lambda
// holding a boost::function is heap-allocated, and its destruction is the write ThreadSanitizer
// reports against that call. So the nodelet passes plain boost::bind objects.
void ConditioningRendererOutputs::advertise(
    image_transport::ImageTransport& it, uint32_t queue_size,
    const image_transport::SubscriberStatusCallback& image_cb,
    const ros::SubscriberStatusCallback& info_cb) {
  image_ =
      it.advertiseCamera("conditioning/image", queue_size, image_cb, image_cb, info_cb, info_cb);
  mask_ = it.advertise("conditioning/mask", queue_size, image_cb, image_cb);
  depth_ = it.advertise("conditioning/depth", queue_size, image_cb, image_cb);
  preview_ = it.advertise("conditioning/preview", queue_size, image_cb, image_cb);
}

bool ConditioningRendererOutputs::anySubscribed() const {
  return image_.getNumSubscribers() > 0 || mask_.getNumSubscribers() > 0 ||
         depth_.getNumSubscribers() > 0 || preview_.getNumSubscribers() > 0;
}

void ConditioningRendererOutputs::publish(const RenderedFrame& frame,
                                          const PinholeIntrinsics& intrinsics,
                                          const ImageSize& size, const std_msgs::Header& header) {
  if (image_.getNumSubscribers() > 0) {
    image_.publish(rc::rgbImageFromBgr(frame.bgr, header),
                   rc::renderedCameraInfo(intrinsics, size, header));
  }
  if (mask_.getNumSubscribers() > 0) mask_.publish(rc::monoImage(frame.mask, header));
  if (depth_.getNumSubscribers() > 0) {
    depth_.publish(rc::renderedDepthImage(frame.depth, frame.mask, header));
  }
  if (preview_.getNumSubscribers() > 0) {
    cv::Mat preview = fillHolesPushPull(frame.bgr, frame.mask);
    drawPreviewLabel(preview);
    preview_.publish(rc::rgbImageFromBgr(preview, header));
  }
}

}  // namespace multimodal_nvs
