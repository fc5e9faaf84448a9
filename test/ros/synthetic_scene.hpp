#pragma once
// A synthetic camera + range-sensor scene with analytic depth, shared by the ROS tests and the
// scene publisher: a fronto-parallel wall at 12 m, a box face at 6 m in front of it, and no
// returns above the horizon band (the "sky"), seen by a 320x240 camera.
#include <geometry_msgs/TransformStamped.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <vector>

#include "multimodal_nvs/ros/conversions.hpp"

namespace synthetic_scene {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
constexpr double kFx = 200.0, kFy = 200.0, kCx = 160.0, kCy = 120.0;
constexpr double kWallDepth = 12.0;
constexpr double kBoxDepth = 6.0;
// The box covers rays with x/z in [-0.25, 0.25] and y/z in [-0.1, 0.25]: pixels u 110..210,
// v 100..170. Range returns exist only for v >= kFirstPointRow.
constexpr double kBoxXMin = -0.25, kBoxXMax = 0.25, kBoxYMin = -0.1, kBoxYMax = 0.25;
constexpr int kFirstPointRow = 96;
constexpr int kPointSpacingPx = 8;  // ~2.3 deg: every pixel below the sky has a point within 2 deg
constexpr const char* kCameraFrame = "scene_camera_optical";
constexpr const char* kSensorFrame = "scene_radar";

/// Camera depth (z) of the scene along pixel (u, v).
inline double analyticDepth(double u, double v) {
  const double x = (u - kCx) / kFx, y = (v - kCy) / kFy;
  const bool on_box = x >= kBoxXMin && x <= kBoxXMax && y >= kBoxYMin && y <= kBoxYMax;
  return on_box ? kBoxDepth : kWallDepth;
}

/// Sensor (x forward, y left, z up, mounted 0.3 m below and 0.5 m behind the camera) -> camera
/// optical frame.
inline Eigen::Isometry3d sensorToCamera() {
  Eigen::Matrix3d axes;
  axes << 0, -1, 0,  //
      0, 0, -1,      //
      1, 0, 0;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = axes;
  t.translation() = Eigen::Vector3d(0.0, 0.3, -0.5);
  return t;
}

inline geometry_msgs::TransformStamped sensorToCameraMsg(const ros::Time& stamp) {
  const Eigen::Isometry3d t = sensorToCamera();
  const Eigen::Quaterniond q(t.linear());
  geometry_msgs::TransformStamped msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = kCameraFrame;  // parent: the transform maps child (sensor) points into it
  msg.child_frame_id = kSensorFrame;
  msg.transform.translation.x = t.translation().x();
  msg.transform.translation.y = t.translation().y();
  msg.transform.translation.z = t.translation().z();
  msg.transform.rotation.x = q.x();
  msg.transform.rotation.y = q.y();
  msg.transform.rotation.z = q.z();
  msg.transform.rotation.w = q.w();
  return msg;
}

inline std_msgs::Header header(const ros::Time& stamp, const char* frame, unsigned seq = 0) {
  std_msgs::Header h;
  h.stamp = stamp;
  h.frame_id = frame;
  h.seq = seq;
  return h;
}

/// Colour of pixel (u, v) as R, G, B.
inline void colourAt(int u, int v, std::uint8_t rgb[3]) {
  rgb[0] = static_cast<std::uint8_t>((u * 7) % 256);
  rgb[1] = static_cast<std::uint8_t>((v * 5) % 256);
  rgb[2] = static_cast<std::uint8_t>(((u + v) * 3) % 256);
}

/// bgr8 image (a channel order the node must swap) with a padded step.
inline sensor_msgs::Image image(const ros::Time& stamp) {
  sensor_msgs::Image img;
  img.header = header(stamp, kCameraFrame);
  img.width = kWidth;
  img.height = kHeight;
  img.encoding = sensor_msgs::image_encodings::BGR8;
  img.step = kWidth * 3 + 8;
  img.data.assign(std::size_t(img.step) * kHeight, 0);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      std::uint8_t rgb[3];
      colourAt(u, v, rgb);
      std::uint8_t* px = &img.data[std::size_t(v) * img.step + 3 * u];
      px[0] = rgb[2];
      px[1] = rgb[1];
      px[2] = rgb[0];
    }
  }
  return img;
}

inline sensor_msgs::CameraInfo cameraInfo(const ros::Time& stamp) {
  sensor_msgs::CameraInfo info;
  info.header = header(stamp, kCameraFrame);
  info.width = kWidth;
  info.height = kHeight;
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {kFx, 0, kCx, 0, kFy, kCy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {kFx, 0, kCx, 0, 0, kFy, kCy, 0, 0, 0, 1, 0};
  return info;
}

/// Scene points in the sensor frame, one per kPointSpacingPx pixels below the sky.
inline std::vector<Eigen::Vector3d> sensorPoints() {
  const Eigen::Isometry3d camera_to_sensor = sensorToCamera().inverse();
  std::vector<Eigen::Vector3d> points;
  for (int v = kFirstPointRow; v < kHeight; v += kPointSpacingPx) {
    for (int u = 0; u < kWidth; u += kPointSpacingPx) {
      const double z = analyticDepth(u, v);
      points.push_back(camera_to_sensor *
                       Eigen::Vector3d((u - kCx) / kFx * z, (v - kCy) / kFy * z, z));
    }
  }
  return points;
}

/// Unorganised cloud: float32 x, y, z plus an extra float32 "intensity" field.
inline sensor_msgs::PointCloud2 cloud(const ros::Time& stamp) {
  std::vector<float> values;
  for (const Eigen::Vector3d& p : sensorPoints()) {
    values.insert(values.end(), {float(p.x()), float(p.y()), float(p.z()), 1.f});
  }
  return multimodal_nvs::ros_conversions::float32Cloud({"x", "y", "z", "intensity"}, values,
                                                       header(stamp, kSensorFrame));
}

/// One synchronized input set of the depth nodelet.
struct InputSet {
  sensor_msgs::PointCloud2 cloud;
  sensor_msgs::Image image;
  sensor_msgs::CameraInfo info;
};

/// The scene's cloud, image and camera_info, all stamped `stamp`.
inline InputSet inputSet(const ros::Time& stamp) {
  return {cloud(stamp), image(stamp), cameraInfo(stamp)};
}

/// Publishers of the depth nodelet's input topics: points, image and camera_info.
class InputPublishers {
 public:
  InputPublishers(ros::NodeHandle& nh, std::uint32_t queue_size)
      : points_(nh.advertise<sensor_msgs::PointCloud2>("points", queue_size)),
        image_(nh.advertise<sensor_msgs::Image>("image", queue_size)),
        info_(nh.advertise<sensor_msgs::CameraInfo>("camera_info", queue_size)) {}

  void publish(const InputSet& set) const {
    points_.publish(set.cloud);
    publishWithoutCloud(set);
  }

  /// Image and camera_info only: a set whose cloud never comes.
  void publishWithoutCloud(const InputSet& set) const {
    image_.publish(set.image);
    info_.publish(set.info);
  }

 private:
  ros::Publisher points_, image_, info_;
};

}  // namespace synthetic_scene
