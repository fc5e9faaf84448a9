// bench_depth_node: feeds a running depth completion node with View-of-Delft radar or LiDAR +
// camera messages at full resolution, and reports end-to-end latency (publish here -> depth/image
// received here), the node's own latency (receipt -> publish, from depth/stats), its compute time,
// and how many scans produced no output. Radar and camera share one rate (--rate); LiDAR
// (--sensor lidar) runs at --points-rate (10 Hz) and the camera at --rate (15 Hz) with their own
// stamps, as real sensors do, so the node's synchroniser pairs each scan with an image. Driven by
// bench/ros/bench_depth_node.sh; not a test.
#include <multimodal_nvs/DepthCompletionStats.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/ros/conversions.hpp"

namespace mm = multimodal_nvs;
using Clock = std::chrono::steady_clock;

namespace {

constexpr const char* kCameraFrame = "vod_camera";
constexpr const char* kSensorFrame = "vod_sensor";

/// The frame's scan as a PointCloud2 with the fields of its VoD file.
sensor_msgs::PointCloud2 sensorCloud(const mm::io::VodFrame& frame, const std::string& sensor) {
  std_msgs::Header header;
  header.frame_id = kSensorFrame;
  if (sensor == "lidar") {
    return mm::ros_conversions::float32Cloud(
        {"x", "y", "z", "intensity"}, mm::io::readFloatRecords(frame.points("lidar"), 4), header);
  }
  return mm::ros_conversions::float32Cloud({"x", "y", "z", "rcs", "v_r", "v_r_compensated", "time"},
                                           mm::io::readFloatRecords(frame.points("radar"), 7),
                                           header);
}

geometry_msgs::TransformStamped extrinsic(const mm::SensorToCamera& tr) {
  // VoD's matrix is not exactly orthonormal; tf carries its nearest rotation.
  const Eigen::Quaterniond q(Eigen::Matrix3d(tr.leftCols<3>()));
  geometry_msgs::TransformStamped t;
  t.header.frame_id = kCameraFrame;
  t.child_frame_id = kSensorFrame;
  t.transform.translation.x = tr(0, 3);
  t.transform.translation.y = tr(1, 3);
  t.transform.translation.z = tr(2, 3);
  const Eigen::Quaterniond n = q.normalized();
  t.transform.rotation.x = n.x();
  t.transform.rotation.y = n.y();
  t.transform.rotation.z = n.z();
  t.transform.rotation.w = n.w();
  return t;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t i = std::min(values.size() - 1, std::size_t(p / 100.0 * values.size()));
  return values[i];
}

std::string argValue(int argc, char** argv, const std::string& name, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (argv[i] == "--" + name) return argv[i + 1];
  }
  return fallback;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "bench_depth_node", ros::init_options::AnonymousName);
  const std::string root = argValue(argc, argv, "vod-root", "../shared/data/vod");
  const std::string sensor = argValue(argc, argv, "sensor", "radar");
  if (sensor != "radar" && sensor != "lidar") {
    ROS_FATAL("--sensor must be radar or lidar, not %s", sensor.c_str());
    return 2;
  }
  const mm::io::VodFrame frame{
      root, mm::io::parseFrameNumber(
                argValue(argc, argv, "frame", sensor == "lidar" ? "00549" : "08350"))};
  const double rate_hz = std::stod(argValue(argc, argv, "rate", "15"));
  // LiDAR at its own rate; radar is published with every image, as before.
  const double points_rate_hz =
      sensor == "lidar" ? std::stod(argValue(argc, argv, "points-rate", "10")) : rate_hz;
  const int frames = std::stoi(argValue(argc, argv, "frames", "150"));
  const bool with_points = argValue(argc, argv, "with-points", "0") == "1";

  const mm::io::KittiCalib calib = mm::io::readKittiCalib(frame.calib(sensor));
  const mm::PinholeIntrinsics k = calib.intrinsics();
  cv::Mat bgr = cv::imread(frame.image(), cv::IMREAD_COLOR);
  if (bgr.empty()) {
    ROS_FATAL("cannot read %s", frame.image().c_str());
    return 1;
  }
  sensor_msgs::Image image;
  image.header.frame_id = kCameraFrame;
  image.height = bgr.rows;
  image.width = bgr.cols;
  image.encoding = sensor_msgs::image_encodings::RGB8;
  image.step = bgr.cols * 3;
  image.data.resize(std::size_t(image.step) * image.height);
  cv::Mat rgb(bgr.rows, bgr.cols, CV_8UC3, image.data.data(), image.step);
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  sensor_msgs::CameraInfo info;
  info.header.frame_id = kCameraFrame;
  info.height = image.height;
  info.width = image.width;
  info.K = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  info.P = {k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
  sensor_msgs::PointCloud2 cloud = sensorCloud(frame, sensor);

  ros::NodeHandle nh;
  tf2_ros::StaticTransformBroadcaster static_tf;
  static_tf.sendTransform(extrinsic(calib.sensorToCamera()));
  ros::Publisher points_pub = nh.advertise<sensor_msgs::PointCloud2>("points", 5);
  ros::Publisher image_pub = nh.advertise<sensor_msgs::Image>("image", 5);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>("camera_info", 5);

  std::mutex mutex;
  std::map<ros::Time, Clock::time_point> sent;
  std::vector<double> end_to_end_ms, node_latency_ms, compute_ms;
  bool measuring = false;
  std::size_t received = 0;
  ros::Subscriber depth_sub = nh.subscribe<sensor_msgs::Image>(
      "depth/image", 10, [&](const sensor_msgs::ImageConstPtr& msg) {
        const Clock::time_point now = Clock::now();
        std::lock_guard<std::mutex> lock(mutex);
        auto it = sent.find(msg->header.stamp);
        // Outputs of the measured stream only (not of the flush below).
        if (!measuring || it != sent.end()) ++received;
        if (measuring && it != sent.end()) {
          end_to_end_ms.push_back(
              std::chrono::duration<double, std::milli>(now - it->second).count());
        }
      });
  ros::Subscriber stats_sub = nh.subscribe<mm::DepthCompletionStats>(
      "depth/stats", 10, [&](const mm::DepthCompletionStatsConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!measuring) return;
        compute_ms.push_back(msg->compute_ms);
        node_latency_ms.push_back(msg->latency_ms);
      });
  ros::Subscriber points_sub;
  if (with_points) {
    const boost::function<void(const sensor_msgs::PointCloud2ConstPtr&)> ignore =
        [](const sensor_msgs::PointCloud2ConstPtr&) {};
    points_sub = nh.subscribe<sensor_msgs::PointCloud2>("depth/points", 2, ignore);
  }
  ros::AsyncSpinner spinner(2);
  spinner.start();

  // The depth image carries the stamp of the image or of the scan it was made from: both are
  // remembered with their publication time.
  auto publishPoints = [&](const ros::Time& stamp) {
    cloud.header.stamp = stamp;
    {
      std::lock_guard<std::mutex> lock(mutex);
      sent[stamp] = Clock::now();
    }
    points_pub.publish(cloud);
  };
  auto publishImage = [&](const ros::Time& stamp) {
    image.header.stamp = info.header.stamp = stamp;
    {
      std::lock_guard<std::mutex> lock(mutex);
      sent.emplace(stamp, Clock::now());
    }
    info_pub.publish(info);
    image_pub.publish(image);
  };
  auto publishSet = [&](const ros::Time& stamp) {
    publishPoints(stamp);
    publishImage(stamp);
  };
  // Warm-up: until the node (lazy) has subscribed and answered; also fills its per-camera caches.
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && ros::WallTime::now() < give_up) {
    publishSet(ros::Time::now());
    ros::WallDuration(0.5).sleep();
    std::lock_guard<std::mutex> lock(mutex);
    if (received >= 3) break;
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (received == 0) {
      ROS_FATAL("the node under test never published depth/image");
      return 1;
    }
    measuring = true;
    received = 0;
    sent.clear();
  }
  // One clock for both streams: every sensor publishes at the first tick at or after its due time.
  const ros::WallTime start = ros::WallTime::now();
  int scans = 0, images = 0;
  while (scans < frames && ros::ok()) {
    const double next_scan = scans / points_rate_hz, next_image = images / rate_hz;
    const double due = std::min(next_scan, next_image);
    const ros::WallTime at = start + ros::WallDuration(due);
    const ros::WallDuration wait = at - ros::WallTime::now();
    if (wait > ros::WallDuration(0)) wait.sleep();
    const ros::Time stamp = ros::Time::now();
    if (sensor == "radar") {
      publishSet(stamp);
      ++scans;
      ++images;
      continue;
    }
    if (next_scan <= due) {
      publishPoints(stamp);
      ++scans;
    }
    if (next_image <= due) {
      publishImage(stamp);
      ++images;
    }
  }
  // An approximate synchronizer forms a set only once a later message shows that no better match
  // can come, so without one more scan and image the last scan of the stream would never be
  // paired. The flush is published unrecorded: its output counts neither as received nor late.
  ros::WallDuration(1.0 / std::min(points_rate_hz, rate_hz)).sleep();
  const ros::Time flush = ros::Time::now();
  cloud.header.stamp = image.header.stamp = info.header.stamp = flush;
  points_pub.publish(cloud);
  info_pub.publish(info);
  image_pub.publish(image);
  ros::WallDuration(2.0).sleep();
  spinner.stop();

  std::lock_guard<std::mutex> lock(mutex);
  std::printf(
      "{\"frame\": \"%s\", \"sensor\": \"%s\", \"image\": \"%dx%d\", \"points\": %u, "
      "\"points_rate_hz\": %.1f, \"image_rate_hz\": %.1f, "
      "\"sent\": %d, \"received\": %zu, \"dropped\": %d, "
      "\"end_to_end_ms\": {\"median\": %.1f, \"p90\": %.1f, \"max\": %.1f}, "
      "\"node_latency_ms\": {\"median\": %.1f, \"p90\": %.1f}, \"compute_ms_median\": %.1f, "
      "\"with_points\": %s}\n",
      frame.id().c_str(), sensor.c_str(), image.width, image.height, cloud.width, points_rate_hz,
      rate_hz, frames, received, frames - int(received), percentile(end_to_end_ms, 50),
      percentile(end_to_end_ms, 90), percentile(end_to_end_ms, 100),
      percentile(node_latency_ms, 50), percentile(node_latency_ms, 90), percentile(compute_ms, 50),
      with_points ? "true" : "false");
  return 0;
}
