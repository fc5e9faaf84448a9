// Latency benchmark of a running ConditioningRenderer in tf mode (not a test): plays a camera of
// H x W pixels with depth on a stride grid (the depth nodelet's output) moving forward along its
// optical axis, publishes `frames` synchronized sets at `rate` Hz with the pose on /tf, and reports
// the end-to-end latency (publish -> conditioning/image received) and the node's own render and
// per-frame times from its diagnostics.
//   bench_renderer [H W stride frames rate preview(0|1)]   defaults: 1216 1936 2 40 5 0
#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/transform_broadcaster.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace enc = sensor_msgs::image_encodings;

int main(int argc, char** argv) {
  ros::init(argc, argv, "bench_renderer");
  const int h = argc > 1 ? std::atoi(argv[1]) : 1216;
  const int w = argc > 2 ? std::atoi(argv[2]) : 1936;
  const int s = argc > 3 ? std::atoi(argv[3]) : 2;
  const int frames = argc > 4 ? std::atoi(argv[4]) : 40;
  const double rate = argc > 5 ? std::atof(argv[5]) : 5.0;
  const bool preview = argc > 6 && std::atoi(argv[6]) != 0;
  // A depth set with every depth_every-th image only (the renderer follows the camera; a slower
  // range sensor only renews the keyframe).
  const int depth_every = argc > 7 ? std::max(1, std::atoi(argv[7])) : 1;
  ros::NodeHandle nh;
  const double f = 0.8 * w, cx = w / 2.0, cy = h / 2.0;

  // The scene: a wall at 20 m with a box face at 8 m in the middle third of the image.
  sensor_msgs::Image image, depth, mask;
  sensor_msgs::CameraInfo info;
  image.height = h;
  image.width = w;
  image.encoding = enc::RGB8;
  image.step = w * 3;
  image.data.resize(std::size_t(h) * w * 3);
  cv::Mat colours(h, w * 3, CV_8UC1, image.data.data());
  cv::RNG(1).fill(colours, cv::RNG::UNIFORM, 0, 256);
  const int gh = (h + s - 1) / s, gw = (w + s - 1) / s;
  depth.height = mask.height = info.height = gh;
  depth.width = mask.width = info.width = gw;
  depth.encoding = enc::TYPE_32FC1;
  depth.step = gw * 4;
  depth.data.resize(std::size_t(gh) * gw * 4);
  mask.encoding = enc::MONO8;
  mask.step = gw;
  mask.data.assign(std::size_t(gh) * gw, 255);
  for (int r = 0; r < gh; ++r) {
    for (int c = 0; c < gw; ++c) {
      const bool box = c * s > w / 3 && c * s < 2 * w / 3 && r * s > h / 3;
      const float z = box ? 8.0f : 20.0f;
      std::memcpy(&depth.data[(std::size_t(r) * gw + c) * 4], &z, 4);
    }
  }
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {f / s, 0, cx / s, 0, f / s, cy / s, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {f / s, 0, cx / s, 0, 0, f / s, cy / s, 0, 0, 0, 1, 0};

  std::mutex mutex;
  std::map<ros::Time, ros::WallTime> sent;
  std::map<ros::Time, int> sent_index;
  std::map<int, double> received_ms;  // frame index -> latency
  std::vector<double> latency_ms;
  std::map<std::string, std::string> diagnostics;
  ros::Subscriber out = nh.subscribe<sensor_msgs::Image>(
      "conditioning/image", 10, [&](const sensor_msgs::ImageConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        auto it = sent.find(msg->header.stamp);
        if (it != sent.end()) {
          latency_ms.push_back((ros::WallTime::now() - it->second).toSec() * 1e3);
          received_ms[sent_index[msg->header.stamp]] = latency_ms.back();
        }
      });
  ros::Subscriber preview_sub;
  if (preview) {
    preview_sub = nh.subscribe<sensor_msgs::Image>("conditioning/preview", 10,
                                                   [&](const sensor_msgs::ImageConstPtr&) {});
  }
  ros::Subscriber diag = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArrayConstPtr& msg) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& status : msg->status) {
          if (status.name.find("conditioning renderer") == std::string::npos) continue;
          for (const auto& kv : status.values)
            diagnostics[kv.key] = kv.value;
        }
      });
  ros::Publisher image_pub = nh.advertise<sensor_msgs::Image>("image", 2);
  ros::Publisher depth_pub = nh.advertise<sensor_msgs::Image>("depth/image", 2);
  ros::Publisher mask_pub = nh.advertise<sensor_msgs::Image>("depth/mask", 2);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>("depth/camera_info", 2);
  tf2_ros::TransformBroadcaster tf;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::WallDuration(2.0).sleep();  // connections (the node subscribes lazily)

  ros::WallRate loop(rate);
  for (int i = 0; i < frames && ros::ok(); ++i) {
    const ros::Time stamp = ros::Time::now();
    geometry_msgs::TransformStamped t;
    t.header.stamp = stamp;
    t.header.frame_id = "odom";
    t.child_frame_id = "bench_camera";
    t.transform.translation.z = 0.05 * i;  // forward along the optical axis
    t.transform.rotation.w = 1.0;
    tf.sendTransform(t);
    for (auto* msg : {&image, &depth, &mask}) {
      msg->header.stamp = stamp;
      msg->header.frame_id = "bench_camera";
    }
    info.header = image.header;
    {
      std::lock_guard<std::mutex> lock(mutex);
      sent[stamp] = ros::WallTime::now();
      sent_index[stamp] = i;
    }
    image_pub.publish(image);
    if (i % depth_every == 0) {
      depth_pub.publish(depth);
      mask_pub.publish(mask);
      info_pub.publish(info);
    }
    loop.sleep();
  }
  ros::WallDuration(3.0).sleep();
  std::lock_guard<std::mutex> lock(mutex);
  std::sort(latency_ms.begin(), latency_ms.end());
  // Which frames never came back, and the latency of the first ones (start-up stalls show there).
  std::string missing, first;
  for (int i = 0; i < frames; ++i) {
    auto it = received_ms.find(i);
    if (it == received_ms.end()) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
    if (i < 12)
      first += (first.empty() ? "" : ", ") +
               (it == received_ms.end() ? std::string("null") : std::to_string(int(it->second)));
  }
  const auto pct = [&](double p) {
    return latency_ms.empty() ? 0.0 : latency_ms[std::size_t(p * (latency_ms.size() - 1))];
  };
  std::printf(
      "{\"image\": [%d, %d], \"depth_stride\": %d, \"sent\": %d, \"received\": %zu, "
      "\"latency_ms\": {\"median\": %.1f, \"p90\": %.1f, \"max\": %.1f}, "
      "\"node_render_mean_ms\": \"%s\", \"node_frame_mean_ms\": \"%s\", \"keyframe_points\": "
      "\"%s\", \"keyframe_cloud_ms\": \"%s\", \"preview\": %s, \"rate_hz\": %g, \"depth_every\": "
      "%d, \"missing\": [%s], \"first_latencies_ms\": [%s], "
      "\"node_camera_images\": \"%s\"}\n",
      h, w, s, frames, latency_ms.size(), pct(0.5), pct(0.9), pct(1.0),
      diagnostics["render mean since start (ms)"].c_str(),
      diagnostics["frame mean since start (ms)"].c_str(), diagnostics["keyframe points"].c_str(),
      diagnostics["keyframe cloud (ms)"].c_str(), preview ? "true" : "false", rate, depth_every,
      missing.c_str(), first.c_str(), diagnostics["camera images total"].c_str());
  return 0;
}
