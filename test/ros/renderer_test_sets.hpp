#pragma once
// A synchronized input set of the conditioning renderer (image, depth/image, depth/mask,
// depth/camera_info) built in memory, for the plain gtests of its ROS layer.
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <cstdint>
#include <cstring>
#include <limits>

namespace {

struct Set {
  sensor_msgs::Image image, depth, mask;
  sensor_msgs::CameraInfo info;
};

/// 12x16 bgr8 image whose pixel (v, u) is (u, v, 7); depth and mask on a stride-`s` grid; depth
/// 2 m with NaN at grid (0, 0).
Set makeSet(int s) {
  Set set;
  set.image.header.frame_id = "cam";
  set.image.height = 12;
  set.image.width = 16;
  set.image.encoding = sensor_msgs::image_encodings::BGR8;
  set.image.step = 16 * 3;
  for (int v = 0; v < 12; ++v) {
    for (int u = 0; u < 16; ++u) {
      set.image.data.push_back(std::uint8_t(u));
      set.image.data.push_back(std::uint8_t(v));
      set.image.data.push_back(7);
    }
  }
  const int gh = (12 + s - 1) / s, gw = (16 + s - 1) / s;
  set.depth.height = set.mask.height = set.info.height = gh;
  set.depth.width = set.mask.width = set.info.width = gw;
  set.depth.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
  set.depth.step = gw * 4;
  set.depth.data.resize(gh * gw * 4);
  for (int i = 0; i < gh * gw; ++i) {
    const float z = i == 0 ? std::numeric_limits<float>::quiet_NaN() : 2.0f;
    std::memcpy(&set.depth.data[i * 4], &z, 4);
  }
  set.mask.encoding = sensor_msgs::image_encodings::MONO8;
  set.mask.step = gw;
  set.mask.data.assign(gh * gw, 255);
  set.info.K = {10.0 / s, 0, 8.0 / s, 0, 10.0 / s, 6.0 / s, 0, 0, 1};
  return set;
}

}  // namespace
