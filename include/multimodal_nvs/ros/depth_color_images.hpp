#pragma once
// Depth and its uncertainty as colour images for people (rviz): bgr8 on the stride grid, over a
// fixed range in metres so that a colour means the same distance in every frame.
#include <sensor_msgs/Image.h>

#include "multimodal_nvs/core/common/colormap.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"

namespace multimodal_nvs {
namespace ros_conversions {

/// Depth (metres) through `scale`; the scale's no-data colour where the pixel is not kept.
void depthColorImage(const DepthMap& depth, const ColorScale& scale, const std_msgs::Header& header,
                     sensor_msgs::Image& image);
/// Standard deviation sqrt(variance) (metres) through `scale`, every pixel with a prediction; the
/// no-data colour where there is none (+inf variance).
void stddevColorImage(const DepthMap& depth, const ColorScale& scale,
                      const std_msgs::Header& header, sensor_msgs::Image& image);

}  // namespace ros_conversions
}  // namespace multimodal_nvs
