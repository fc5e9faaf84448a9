#include "multimodal_nvs/ros/depth_color_images.hpp"

#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <cstring>

#include "message_helpers.hpp"

namespace multimodal_nvs {
namespace ros_conversions {
namespace {

/// Shapes `image` as bgr8 on the depth map's grid and writes colour(i) for every grid pixel i.
template <class Colour>
void colourImage(const DepthMap& depth, const std_msgs::Header& header, sensor_msgs::Image& image,
                 const Colour& colour) {
  detail::shapeImage(image, depth.grid.rows(), depth.grid.cols(),
                     sensor_msgs::image_encodings::BGR8, 3, header);
  std::uint8_t* out = image.data.data();
  const std::size_t count = depth.depth.size();
  for (std::size_t i = 0; i < count; ++i) {
    const cv::Vec3b bgr = colour(i);
    std::memcpy(out + 3 * i, bgr.val, 3);
  }
}

}  // namespace

void depthColorImage(const DepthMap& depth, const ColorScale& scale, const std_msgs::Header& header,
                     sensor_msgs::Image& image) {
  colourImage(depth, header, image, [&](std::size_t i) {
    return depth.valid[i] ? scale(depth.depth[i]) : scale.noData();
  });
}

void stddevColorImage(const DepthMap& depth, const ColorScale& scale,
                      const std_msgs::Header& header, sensor_msgs::Image& image) {
  // sqrt(+inf) = +inf: no prediction takes the no-data colour.
  colourImage(depth, header, image,
              [&](std::size_t i) { return scale(std::sqrt(depth.variance[i])); });
}

}  // namespace ros_conversions
}  // namespace multimodal_nvs
