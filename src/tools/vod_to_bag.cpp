// vod_to_bag: a View-of-Delft layout directory (the View-of-Delft layout, also what
// make_synthetic_scene writes) as a ROS bag: camera image + camera_info, radar and LiDAR clouds,
// static extrinsics and the camera trajectory on /tf.
//
// Frames and time: the selected frames are sorted by number and stamped start_time + i / rate
// (i = 0, 1, ...), whatever gaps there are in the numbering. Every message of a frame carries the
// same stamp, as header stamp and as bag time.
//
// World frame: a VoD pose file holds the camera pose in three worlds (odomToCamera, mapToCamera,
// UTMToCamera). /tf gets one of them as WORLD -> camera, by default odomToCamera under the frame
// `odom`: odometry is the smooth, continuous world that tf consumers and rviz expect of `odom`
// (map poses may jump when localisation corrects itself, and UTM coordinates of ~6e6 m lose
// precision in float renderers). `--pose-key mapToCamera` publishes `map` -> camera instead (the
// world the reference renderer uses; relative poses within a short sequence are the same), and
// `--world-frame` overrides the frame name.
//
// Frame names follow REP 103: the camera's frame is an optical frame (z forward, x right, y down,
// the convention of image and camera_info), so it carries the `_optical` suffix
// (`camera_optical`); `radar` and `lidar` are body frames of their sensors (x forward, z up).
#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_msgs/TFMessage.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "common/cli.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/camera_info_yaml.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "multimodal_nvs/ros/conversions.hpp"

namespace mm = multimodal_nvs;
namespace fs = std::filesystem;

namespace {

struct Options {
  std::string root, output, pose_key, world_frame;
  std::string camera_frame = "camera_optical", radar_frame = "radar", lidar_frame = "lidar";
  int first = 0, last = 99999;
  double rate = 10.0, start_time = 1.0;
  bool compressed = false, quiet = false;
  std::string compression = "none";
};

/// Which files exist for each frame number.
struct FrameFiles {
  bool image = false, pose = false;
  bool points[2] = {false, false};  // radar, lidar
  bool calib[2] = {false, false};
};
const char* const kSensors[2] = {"radar", "lidar"};

void declareOptions(mm::cli::Args& args) {
  args.option("vod-root", 1, "View-of-Delft layout root (ROOT/lidar/training/..., ROOT/radar/...)");
  args.option("output", 1, "bag file to write");
  args.option("frames", 1, "frame range A-B (inclusive), e.g. 8350-8365 (default: all)");
  args.option("rate", 1, "frames per second of the stamps", "10");
  args.option("start-time", 1, "stamp of the first frame, seconds", "1");
  args.option("pose-key", 1, "pose file key published on /tf", "odomToCamera");
  args.option("world-frame", 1, "parent frame of the camera on /tf (default: odom|map|utm by key)");
  args.option("camera-frame", 1, "camera optical frame id (REP 103)", "camera_optical");
  args.option("radar-frame", 1, "radar frame id", "radar");
  args.option("lidar-frame", 1, "LiDAR frame id", "lidar");
  args.option("compression", 1, "bag chunk compression: none|lz4|bz2", "none");
  args.flag("compressed", "write /camera/image_raw/compressed with the JPEG bytes instead of raw");
  args.flag("quiet", "no progress bar");
}

std::pair<int, int> parseRange(const std::string& text) {
  const auto dash = text.find('-');
  if (dash == std::string::npos || dash == 0) {
    const int f = mm::io::parseFrameNumber(text);
    return {f, f};
  }
  const int a = mm::io::parseFrameNumber(text.substr(0, dash));
  const int b = mm::io::parseFrameNumber(text.substr(dash + 1));
  if (b < a) throw mm::cli::UsageError("--frames " + text + ": the range is empty (B < A)");
  return {a, b};
}

std::string defaultWorldFrame(const std::string& key) {
  if (key == "odomToCamera") return "odom";
  if (key == "mapToCamera") return "map";
  if (key == "UTMToCamera") return "utm";
  std::string lower = key.substr(0, key.find("To"));
  std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
  return lower.empty() ? "world" : lower;
}

Options parseOptions(const mm::cli::Args& args) {
  Options o;
  if (!args.has("vod-root")) throw mm::cli::UsageError("--vod-root DIR is required");
  if (!args.has("output")) throw mm::cli::UsageError("--output BAG is required");
  o.root = args.str("vod-root");
  o.output = args.str("output");
  if (args.has("frames")) std::tie(o.first, o.last) = parseRange(args.str("frames"));
  o.rate = args.number("rate", o.rate);
  if (!(o.rate > 0.0) || !std::isfinite(o.rate)) throw mm::cli::UsageError("--rate must be > 0");
  o.start_time = args.number("start-time", o.start_time);
  if (!(o.start_time > 0.0) || o.start_time > 4e9) {
    throw mm::cli::UsageError("--start-time must be in (0, 4e9] seconds (ROS time 0 means unset)");
  }
  o.pose_key = args.str("pose-key", "odomToCamera");
  o.world_frame = args.has("world-frame") ? args.str("world-frame") : defaultWorldFrame(o.pose_key);
  o.camera_frame = args.str("camera-frame", o.camera_frame);
  o.radar_frame = args.str("radar-frame", o.radar_frame);
  o.lidar_frame = args.str("lidar-frame", o.lidar_frame);
  o.compression = args.str("compression", o.compression);
  if (o.compression != "none" && o.compression != "lz4" && o.compression != "bz2") {
    throw mm::cli::UsageError("--compression must be none, lz4 or bz2");
  }
  o.compressed = args.has("compressed");
  o.quiet = args.has("quiet");
  return o;
}

/// Frame numbers of the NNNNN.ext files in `dir` (other names are ignored).
std::set<int> framesIn(const std::string& dir, const std::string& ext) {
  std::set<int> frames;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return frames;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const fs::path p = entry.path();
    if (p.extension() != ext) continue;
    const std::string stem = p.stem().string();
    if (stem.empty() || stem.size() > 6 ||
        !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      continue;
    }
    frames.insert(std::stoi(stem));
  }
  return frames;
}

std::map<int, FrameFiles> discoverFrames(const Options& o) {
  std::map<int, FrameFiles> frames;
  auto mark = [&](const std::string& dir, const std::string& ext, auto setter) {
    for (int f : framesIn(o.root + dir, ext)) {
      if (f >= o.first && f <= o.last) setter(frames[f]);
    }
  };
  mark("/lidar/training/image_2", ".jpg", [](FrameFiles& f) { f.image = true; });
  mark("/lidar/training/pose", ".json", [](FrameFiles& f) { f.pose = true; });
  for (int s = 0; s < 2; ++s) {
    const std::string base = std::string("/") + kSensors[s] + "/training/";
    mark(base + "velodyne", ".bin", [s](FrameFiles& f) { f.points[s] = true; });
    mark(base + "calib", ".txt", [s](FrameFiles& f) { f.calib[s] = true; });
  }
  if (frames.empty()) {
    std::ostringstream msg;
    msg << o.root << ": no View-of-Delft frame";
    if (o.first > 0 || o.last < 99999) msg << " in " << o.first << "-" << o.last;
    msg << " (expected lidar/training/image_2/NNNNN.jpg, lidar/training/pose/NNNNN.json or "
           "{radar,lidar}/training/velodyne/NNNNN.bin)";
    throw mm::InputError(msg.str());
  }
  return frames;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw mm::InputError(path + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Sensor -> camera as a rigid transform; the rotation of a calibration printed with few digits is
/// projected to the nearest rotation. Throws when it is not close to one.
Eigen::Isometry3d rigidFromCalib(const mm::SensorToCamera& m, const std::string& source) {
  const Eigen::Matrix3d r = m.leftCols<3>();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d nearest = svd.matrixU() * svd.matrixV().transpose();
  if (!m.allFinite() || nearest.determinant() < 0.0 || (nearest - r).cwiseAbs().maxCoeff() > 1e-2) {
    throw mm::InputError(source +
                         ": Tr_velo_to_cam is not a rigid transform (rotation part is "
                         "not orthonormal with determinant +1)");
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = nearest;
  t.translation() = m.col(3);
  return t;
}

geometry_msgs::TransformStamped toTransform(const Eigen::Isometry3d& t, const ros::Time& stamp,
                                            const std::string& parent, const std::string& child) {
  geometry_msgs::TransformStamped msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = parent;
  msg.child_frame_id = child;
  msg.transform.translation.x = t.translation().x();
  msg.transform.translation.y = t.translation().y();
  msg.transform.translation.z = t.translation().z();
  const Eigen::Quaterniond q(t.linear());
  msg.transform.rotation.x = q.x();
  msg.transform.rotation.y = q.y();
  msg.transform.rotation.z = q.z();
  msg.transform.rotation.w = q.w();
  return msg;
}

sensor_msgs::PointCloud2 toCloud(const std::string& path, const std::vector<std::string>& names,
                                 const std::string& frame, const ros::Time& stamp) {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = frame;
  return mm::ros_conversions::float32Cloud(
      names, mm::io::readFloatRecords(path, static_cast<int>(names.size())), header);
}

/// `lens`: the distortion of the frame's camera_info YAML (none without one).
sensor_msgs::CameraInfo toCameraInfo(const mm::io::KittiCalib& calib, int width, int height,
                                     const std::string& frame, const ros::Time& stamp,
                                     const mm::LensDistortion& lens) {
  const auto& p = calib.numbers("P2", 12);
  calib.intrinsics().validate(calib.source);
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = frame;
  info.width = static_cast<std::uint32_t>(width);
  info.height = static_cast<std::uint32_t>(height);
  info.distortion_model = lens.any() ? lens.rosName() : "plumb_bob";
  info.D.assign(lens.coefficients.begin(),
                lens.coefficients.begin() + std::max(5, lens.coefficientCount()));
  info.K = {p[0], p[1], p[2], p[4], p[5], p[6], p[8], p[9], p[10]};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int i = 0; i < 12; ++i)
    info.P[i] = p[i];
  return info;
}

class BagWriter {
 public:
  BagWriter(const Options& o, const std::string& path) {
    bag_.open(path, rosbag::bagmode::Write);
    if (o.compression == "lz4") bag_.setCompression(rosbag::compression::LZ4);
    if (o.compression == "bz2") bag_.setCompression(rosbag::compression::BZ2);
  }

  template <class T>
  void write(const std::string& topic, const ros::Time& stamp, const T& msg) {
    bag_.write(topic, stamp, msg);
    ++counts_[topic];
  }

  /// /tf_static as a latched connection, as tf2_ros::StaticTransformBroadcaster publishes it.
  void writeStatic(const ros::Time& stamp, const tf2_msgs::TFMessage& msg) {
    auto header = boost::make_shared<ros::M_string>();
    (*header)["type"] = ros::message_traits::datatype(msg);
    (*header)["md5sum"] = ros::message_traits::md5sum(msg);
    (*header)["message_definition"] = ros::message_traits::definition(msg);
    (*header)["callerid"] = "/vod_to_bag";
    (*header)["latching"] = "1";
    bag_.write("/tf_static", stamp, msg, header);
    ++counts_["/tf_static"];
  }

  void close() { bag_.close(); }
  const std::map<std::string, int>& counts() const { return counts_; }

 private:
  rosbag::Bag bag_;
  std::map<std::string, int> counts_;
};

void progressBar(int done, int total) {
  const int width = 30, filled = done * width / total;
  std::cerr << "\rvod_to_bag [" << std::string(filled, '#') << std::string(width - filled, '.')
            << "] " << done << "/" << total << " frames" << (done == total ? "\n" : "")
            << std::flush;
}

int run(int argc, char** argv) {
  mm::cli::Args args("vod_to_bag",
                     "Converts a View-of-Delft layout directory into a ROS bag (camera, "
                     "camera_info, radar and LiDAR clouds, /tf_static extrinsics, /tf poses).");
  declareOptions(args);
  if (!args.parse(argc, argv)) return 0;
  const Options o = parseOptions(args);
  const std::map<int, FrameFiles> frames = discoverFrames(o);

  // Validate everything that spans frames before writing: the intrinsics for camera_info and an
  // extrinsic for every sensor that has points.
  std::optional<mm::io::KittiCalib> first_intrinsics;
  std::optional<Eigen::Isometry3d> extrinsic[2];
  bool any_image = false, any_points[2] = {false, false};
  for (const auto& [number, files] : frames) {
    const mm::io::VodFrame vod{o.root, number};
    any_image = any_image || files.image;
    for (int s = 0; s < 2; ++s) {
      any_points[s] = any_points[s] || files.points[s];
      if (!files.calib[s]) continue;
      const mm::io::KittiCalib calib = mm::io::readKittiCalib(vod.calib(kSensors[s]));
      if (!extrinsic[s]) extrinsic[s] = rigidFromCalib(calib.sensorToCamera(), calib.source);
      if (!first_intrinsics) first_intrinsics = calib;
    }
  }
  if (any_image && !first_intrinsics) {
    throw mm::InputError(o.root +
                         ": images but no calib file in the selected frames (camera_info "
                         "needs P2 from {radar,lidar}/training/calib/NNNNN.txt)");
  }
  for (int s = 0; s < 2; ++s) {
    if (any_points[s] && !extrinsic[s]) {
      throw mm::InputError(o.root + ": " + kSensors[s] + " scans but no " + kSensors[s] +
                           "/training/calib/NNNNN.txt in the selected frames (Tr_velo_to_cam "
                           "needed for the " +
                           kSensors[s] + " frame)");
    }
  }
  int expected = frames.begin()->first;
  for (const auto& entry : frames) {
    if (entry.first != expected++) {
      std::cerr << "vod_to_bag: note: frame numbers are not consecutive; stamps are spaced 1/rate "
                   "apart anyway\n";
      break;
    }
  }

  // Written under a temporary name and renamed when complete, so that a failure half-way leaves
  // no truncated bag behind.
  const std::string partial = o.output + ".partial";
  struct RemoveOnFailure {
    std::string path;
    bool done = false;
    ~RemoveOnFailure() {
      if (!done) std::remove(path.c_str());
    }
  } cleanup{partial};
  BagWriter bag(o, partial);
  const std::string frame_ids[2] = {o.radar_frame, o.lidar_frame};
  const std::vector<std::string> fields[2] = {
      {"x", "y", "z", "rcs", "v_r", "v_r_compensated", "time"}, {"x", "y", "z", "intensity"}};
  const std::string points_topics[2] = {"/radar/points", "/lidar/points"};
  const ros::Time start(o.start_time);

  auto staticMessage = [&](const ros::Time& stamp) {
    tf2_msgs::TFMessage msg;
    for (int s = 0; s < 2; ++s) {
      if (extrinsic[s]) {
        msg.transforms.push_back(toTransform(*extrinsic[s], stamp, o.camera_frame, frame_ids[s]));
      }
    }
    return msg;
  };
  if (extrinsic[0] || extrinsic[1]) bag.writeStatic(start, staticMessage(start));

  mm::io::KittiCalib intrinsics = first_intrinsics.value_or(mm::io::KittiCalib());
  int index = 0;
  const int total = static_cast<int>(frames.size());
  for (const auto& [number, files] : frames) {
    const mm::io::VodFrame vod{o.root, number};
    const ros::Time stamp = start + ros::Duration(index / o.rate);

    // Per-frame calibrations: the latest one gives camera_info; a changed extrinsic is
    // re-published on /tf_static.
    bool extrinsic_changed = false;
    for (int s = 0; s < 2; ++s) {
      if (!files.calib[s]) continue;
      const mm::io::KittiCalib calib = mm::io::readKittiCalib(vod.calib(kSensors[s]));
      const Eigen::Isometry3d t = rigidFromCalib(calib.sensorToCamera(), calib.source);
      if (!t.isApprox(*extrinsic[s], 1e-9)) {
        extrinsic[s] = t;
        extrinsic_changed = true;
      }
      if (s == 1 || !files.calib[1]) intrinsics = calib;  // prefer the LiDAR calib's P2
    }
    if (extrinsic_changed) bag.writeStatic(stamp, staticMessage(stamp));

    if (files.pose) {
      const Eigen::Matrix4d pose = mm::io::readVodPose(vod.pose(), o.pose_key);
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(
          toTransform(Eigen::Isometry3d(pose), stamp, o.world_frame, o.camera_frame));
      bag.write("/tf", stamp, tf);
    }

    if (files.image) {
      const std::string bytes = readBytes(vod.image());
      const cv::Mat bgr = cv::imdecode(
          cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data())),
          cv::IMREAD_COLOR);
      if (bgr.empty()) throw mm::InputError(vod.image() + ": cannot decode image");
      if (o.compressed) {
        sensor_msgs::CompressedImage msg;
        msg.header.stamp = stamp;
        msg.header.frame_id = o.camera_frame;
        const bool png = bytes.size() > 4 && bytes.compare(1, 3, "PNG") == 0;
        msg.format = png ? "rgb8; png compressed bgr8" : "rgb8; jpeg compressed bgr8";
        msg.data.assign(bytes.begin(), bytes.end());
        bag.write("/camera/image_raw/compressed", stamp, msg);
      } else {
        sensor_msgs::Image msg;
        msg.header.stamp = stamp;
        msg.header.frame_id = o.camera_frame;
        msg.height = static_cast<std::uint32_t>(bgr.rows);
        msg.width = static_cast<std::uint32_t>(bgr.cols);
        msg.encoding = sensor_msgs::image_encodings::RGB8;
        msg.is_bigendian = 0;
        msg.step = static_cast<std::uint32_t>(3 * bgr.cols);
        msg.data.resize(static_cast<std::size_t>(msg.step) * msg.height);
        cv::Mat rgb(bgr.rows, bgr.cols, CV_8UC3, msg.data.data(), msg.step);
        cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
        bag.write("/camera/image_raw", stamp, msg);
      }
      const std::string lens_yaml = vod.cameraInfo(files.calib[1] ? "lidar" : "radar");
      const mm::LensDistortion lens =
          mm::io::fileExists(lens_yaml)
              ? mm::io::frameIntrinsics(intrinsics, lens_yaml, {bgr.rows, bgr.cols}).distortion
              : mm::LensDistortion();
      bag.write("/camera/camera_info", stamp,
                toCameraInfo(intrinsics, bgr.cols, bgr.rows, o.camera_frame, stamp, lens));
    }

    for (int s = 0; s < 2; ++s) {
      if (!files.points[s]) continue;
      bag.write(points_topics[s], stamp,
                toCloud(vod.points(kSensors[s]), fields[s], frame_ids[s], stamp));
    }
    ++index;
    if (!o.quiet) progressBar(index, total);
  }
  bag.close();
  std::error_code ec;
  fs::rename(partial, o.output, ec);
  if (ec) throw mm::InputError(o.output + ": cannot write (" + ec.message() + ")");
  cleanup.done = true;

  std::ostringstream json;
  json << "{\"bag\": \"" << mm::cli::jsonEscape(o.output) << "\", \"frames\": " << total
       << ", \"first_frame\": " << frames.begin()->first
       << ", \"last_frame\": " << frames.rbegin()->first << ", \"start_time\": " << o.start_time
       << ", \"rate\": " << o.rate << ", \"world_frame\": \"" << mm::cli::jsonEscape(o.world_frame)
       << "\", \"messages\": {";
  bool first = true;
  for (const auto& [topic, count] : bag.counts()) {
    json << (first ? "" : ", ") << "\"" << topic << "\": " << count;
    first = false;
  }
  json << "}}";
  std::cout << json.str() << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("vod_to_bag", run, argc, argv);
}
