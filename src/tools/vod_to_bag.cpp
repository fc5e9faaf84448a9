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
#include "common/frame_options.hpp"
#include "common/progress.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/json_output.hpp"
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
  std::string root, output, pose_key = mm::io::odometryVodPoseKey(), world_frame;
  std::string camera_frame = "camera_optical", radar_frame = "radar", lidar_frame = "lidar";
  mm::cli::FrameOptions frames;
  std::set<int> selected;  // empty: every frame found
  double rate = 10.0, start_time = 1.0;
  bool compressed = false, quiet = false;
  std::string compression = "none";

  bool wanted(int frame) const { return selected.empty() || selected.count(frame) > 0; }
};

/// Which files exist for each frame number.
struct FrameFiles {
  bool image = false, pose = false;
  bool points[2] = {false, false};  // radar, lidar
  bool calib[2] = {false, false};
};
const char* const kSensors[2] = {"radar", "lidar"};

void declareOptions(CLI::App& app, Options& o) {
  const char* in = mm::cli::kRequired;
  app.add_option("--vod-root", o.root,
                 "View-of-Delft layout root (ROOT/lidar/training/..., ROOT/radar/...)")
      ->required()
      ->group(in);
  app.add_option("--output", o.output, "bag file to write")->required()->group(in);
  mm::cli::declareFrameOptions(app, o.frames, mm::cli::kInputs,
                               "frames, e.g. 8350-8365 or 549,1047 (default: all)", false);
  mm::cli::declarePoseKeyOption(app, o.pose_key, mm::cli::kInputs, "published on /tf");
  const char* out = mm::cli::kOutput;
  app.add_option("--rate", o.rate, "frames per second of the stamps")
      ->check(mm::cli::positive())
      ->group(out);
  app.add_option("--start-time", o.start_time,
                 "stamp of the first frame, seconds, in (0, 4e9] (ROS time 0 means unset)")
      ->check(mm::cli::positive())
      ->check(CLI::Range(0.0, 4e9))
      ->group(out);
  app.add_option("--world-frame", o.world_frame,
                 "parent frame of the camera on /tf (default: odom|map|utm by key)")
      ->group(out);
  app.add_option("--camera-frame", o.camera_frame, "camera optical frame id (REP 103)")->group(out);
  app.add_option("--radar-frame", o.radar_frame, "radar frame id")->group(out);
  app.add_option("--lidar-frame", o.lidar_frame, "LiDAR frame id")->group(out);
  app.add_option("--compression", o.compression, "bag chunk compression: none|lz4|bz2")
      ->check(CLI::IsMember({"none", "lz4", "bz2"}))
      ->group(out);
  app.add_flag("--compressed", o.compressed,
               "write /camera/image_raw/compressed with the JPEG bytes instead of raw")
      ->group(out);
  app.add_flag("--quiet", o.quiet, "no progress or throughput on stderr")->group(mm::cli::kOptions);
}

std::string defaultWorldFrame(const std::string& key) {
  if (key == "odomToCamera") return "odom";
  if (key == "mapToCamera") return "map";
  if (key == "UTMToCamera") return "utm";
  std::string lower = key.substr(0, key.find("To"));
  std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
  return lower.empty() ? "world" : lower;
}

void finishOptions(Options& o) {
  if (o.world_frame.empty()) o.world_frame = defaultWorldFrame(o.pose_key);
  if (mm::cli::framesGiven(o.frames)) {
    const std::vector<int> frames = mm::cli::selectedFrames(o.frames);
    o.selected.insert(frames.begin(), frames.end());
  }
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
      if (o.wanted(f)) setter(frames[f]);
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
    if (!o.selected.empty()) msg << " among the " << o.selected.size() << " selected by --frames";
    msg << " (expected lidar/training/image_2/NNNNN.jpg, lidar/training/pose/NNNNN.json or "
           "{radar,lidar}/training/velodyne/NNNNN.bin)";
    throw mm::InputError(msg.str());
  }
  return frames;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw mm::InputError(path + ": cannot open (" + std::strerror(errno) + ")");
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

int run(int argc, char** argv) {
  CLI::App app(
      "Converts a View-of-Delft layout directory into a ROS bag (camera, camera_info, "
      "radar and LiDAR clouds, /tf_static extrinsics, /tf poses).",
      "vod_to_bag");
  mm::cli::setUp(app, "vod_to_bag --vod-root data/vod --frames 8350-8365 --output vod.bag");
  Options o;
  declareOptions(app, o);
  if (!mm::cli::parse(app, argc, argv)) return 0;
  finishOptions(o);
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
  // Recorded 0.1 s before the first frame (its transforms keep the first frame's stamp): inside
  // one `rosbag play` the extrinsic and a first scan with the same time race, and a single radar
  // scan whose sensor -> camera transform is not there yet is dropped by the depth nodelet.
  const ros::Time static_time = start - ros::Duration(std::min(0.1, start.toSec()));
  if (extrinsic[0] || extrinsic[1]) bag.writeStatic(static_time, staticMessage(start));

  mm::io::KittiCalib intrinsics = first_intrinsics.value_or(mm::io::KittiCalib());
  int index = 0;
  const int total = static_cast<int>(frames.size());
  mm::cli::Progress progress("vod_to_bag", total, "frames", o.quiet);
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
    progress.step(vod.id());
  }
  bag.close();
  std::error_code ec;
  fs::rename(partial, o.output, ec);
  if (ec) throw mm::InputError(o.output + ": cannot write (" + ec.message() + ")");
  cleanup.done = true;
  progress.finish();

  mm::json::Json messages = mm::json::Json::object();
  for (const auto& [topic, count] : bag.counts())
    messages[topic] = count;
  const mm::json::Json json = {{"bag", o.output},
                               {"frames", total},
                               {"first_frame", frames.begin()->first},
                               {"last_frame", frames.rbegin()->first},
                               {"start_time", mm::json::number(o.start_time, 6)},
                               {"rate", mm::json::number(o.rate, 6)},
                               {"world_frame", o.world_frame},
                               {"messages", messages}};
  std::cout << mm::json::oneLine(json) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("vod_to_bag", run, argc, argv);
}
