// vod_to_bag round trip without a ROS master: a tiny synthetic scene (made here with the core),
// converted by the tool, read back with rosbag. The bag must hold exactly the files: message
// counts, stamps, cloud fields and bytes, image pixels, camera_info, static and moving transforms.
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sys/wait.h>
#include <tf2_msgs/TFMessage.h>
#include "tool_runner.hpp"

#include <Eigen/Geometry>
#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"
#include "multimodal_nvs/core/synthetic/dataset.hpp"

namespace io = multimodal_nvs::io;
namespace syn = multimodal_nvs::synthetic;
namespace fs = std::filesystem;

namespace {

constexpr int kFrames = 3;

using multimodal_nvs::test::ToolResult;

ToolResult runTool(const std::string& args) {
  return multimodal_nvs::test::runTool("vod_to_bag", args);
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The scene is made once for all tests: scale 0.1 (194 x 122), 3 frames from 120.
const std::string& sceneRoot() {
  static const std::string root = [] {
    const std::string dir = ::testing::TempDir() + "vod_to_bag_scene";
    fs::remove_all(dir);
    syn::SyntheticDatasetParams p;
    p.seed = 21;
    p.frames = kFrames;
    p.first_frame = 120;
    p.scale = 0.1;
    p.lidar.azimuth_step_deg = 2.0;
    syn::SyntheticDataset(p).write(dir);
    return dir;
  }();
  return root;
}

/// A writable copy of the scene for tests that damage files.
std::string copyScene(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "vod_to_bag_" + name;
  fs::remove_all(dir);
  fs::copy(sceneRoot(), dir, fs::copy_options::recursive);
  return dir;
}

struct BagContents {
  std::map<std::string, std::vector<rosbag::MessageInstance>> by_topic;
  std::map<std::string, std::string> latching;
};

/// Reads every message of `path`; the MessageInstances stay valid while `bag` is open.
BagContents readBag(rosbag::Bag& bag, const std::string& path) {
  bag.open(path, rosbag::bagmode::Read);
  BagContents contents;
  rosbag::View view(bag);
  for (const rosbag::MessageInstance& m : view) {
    contents.by_topic[m.getTopic()].push_back(m);
    const auto header = m.getConnectionHeader();
    if (header && header->count("latching"))
      contents.latching[m.getTopic()] = header->at("latching");
  }
  return contents;
}

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() =
      Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).toRotationMatrix();
  out.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return out;
}

void expectFields(const sensor_msgs::PointCloud2& cloud, const std::vector<std::string>& names) {
  ASSERT_EQ(cloud.fields.size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(cloud.fields[i].name, names[i]);
    EXPECT_EQ(cloud.fields[i].offset, 4 * i);
    EXPECT_EQ(cloud.fields[i].datatype, sensor_msgs::PointField::FLOAT32);
    EXPECT_EQ(cloud.fields[i].count, 1u);
  }
  EXPECT_EQ(cloud.point_step, 4 * names.size());
  EXPECT_EQ(cloud.height, 1u);
  EXPECT_EQ(cloud.row_step, cloud.point_step * cloud.width);
  EXPECT_FALSE(cloud.is_bigendian);
}

}  // namespace

TEST(VodToBag, RoundTripEqualsTheFiles) {
  const std::string root = sceneRoot();
  const std::string bag_path = ::testing::TempDir() + "vod_to_bag_round_trip.bag";
  const auto r = runTool("--vod-root " + root + " --output " + bag_path +
                         " --rate 5 --start-time 100.5 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"frames\": 3"), std::string::npos) << r.output;

  rosbag::Bag bag;
  BagContents bag_contents = readBag(bag, bag_path);
  auto& topics = bag_contents.by_topic;
  for (const char* topic :
       {"/camera/image_raw", "/camera/camera_info", "/radar/points", "/lidar/points", "/tf"}) {
    EXPECT_EQ(topics[topic].size(), static_cast<std::size_t>(kFrames)) << topic;
  }
  ASSERT_EQ(topics["/tf_static"].size(), 1u);
  EXPECT_EQ(bag_contents.latching["/tf_static"], "1");
  EXPECT_EQ(topics.size(), 6u);

  // Static transforms: camera -> radar and camera -> lidar are the calibrations' Tr_velo_to_cam.
  const auto statics = topics["/tf_static"][0].instantiate<tf2_msgs::TFMessage>();
  ASSERT_TRUE(statics);
  ASSERT_EQ(statics->transforms.size(), 2u);
  const io::VodFrame first{root, 120};
  for (const auto& t : statics->transforms) {
    EXPECT_EQ(t.header.frame_id, "camera_optical");
    ASSERT_TRUE(t.child_frame_id == "radar" || t.child_frame_id == "lidar") << t.child_frame_id;
    const auto expected = io::readKittiCalib(first.calib(t.child_frame_id)).sensorToCamera();
    EXPECT_LT((toIsometry(t.transform).matrix().topRows<3>() - expected).cwiseAbs().maxCoeff(),
              1e-9)
        << t.child_frame_id;
  }

  for (int i = 0; i < kFrames; ++i) {
    SCOPED_TRACE("frame " + std::to_string(120 + i));
    const io::VodFrame f{root, 120 + i};
    const ros::Time stamp(100.5 + i / 5.0);

    // Image: rgb8 pixels equal the decoded JPEG.
    const auto& image_instance = topics["/camera/image_raw"][i];
    EXPECT_EQ(image_instance.getTime(), stamp);
    const auto image = image_instance.instantiate<sensor_msgs::Image>();
    ASSERT_TRUE(image);
    EXPECT_EQ(image->header.stamp, stamp);
    EXPECT_EQ(image->header.frame_id, "camera_optical");
    EXPECT_EQ(image->encoding, "rgb8");
    const cv::Mat bgr = cv::imread(f.image(), cv::IMREAD_COLOR);
    ASSERT_EQ(image->width, static_cast<std::uint32_t>(bgr.cols));
    ASSERT_EQ(image->height, static_cast<std::uint32_t>(bgr.rows));
    ASSERT_EQ(image->step, 3u * bgr.cols);
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    EXPECT_EQ(std::memcmp(image->data.data(), rgb.data, image->data.size()), 0);

    // camera_info: P2 and the image size.
    const auto info = topics["/camera/camera_info"][i].instantiate<sensor_msgs::CameraInfo>();
    ASSERT_TRUE(info);
    EXPECT_EQ(info->header.stamp, stamp);
    EXPECT_EQ(info->header.frame_id, "camera_optical");
    EXPECT_EQ(info->width, image->width);
    EXPECT_EQ(info->height, image->height);
    const auto k = io::readKittiCalib(f.calib("lidar")).intrinsics();
    EXPECT_DOUBLE_EQ(info->K[0], k.fx);
    EXPECT_DOUBLE_EQ(info->K[2], k.cx);
    EXPECT_DOUBLE_EQ(info->K[4], k.fy);
    EXPECT_DOUBLE_EQ(info->K[5], k.cy);
    EXPECT_DOUBLE_EQ(info->K[8], 1.0);
    EXPECT_DOUBLE_EQ(info->P[0], k.fx);
    EXPECT_DOUBLE_EQ(info->P[10], 1.0);

    // Clouds: the fields of the VoD records, and the very bytes of the .bin files.
    const auto radar = topics["/radar/points"][i].instantiate<sensor_msgs::PointCloud2>();
    ASSERT_TRUE(radar);
    EXPECT_EQ(topics["/radar/points"][i].getTime(), stamp);
    EXPECT_EQ(radar->header.stamp, stamp);
    EXPECT_EQ(radar->header.frame_id, "radar");
    expectFields(*radar, {"x", "y", "z", "rcs", "v_r", "v_r_compensated", "time"});
    const std::string radar_bytes = readBytes(f.points("radar"));
    EXPECT_EQ(radar->width * 28u, radar_bytes.size());
    EXPECT_TRUE(std::string(radar->data.begin(), radar->data.end()) == radar_bytes);

    const auto lidar = topics["/lidar/points"][i].instantiate<sensor_msgs::PointCloud2>();
    ASSERT_TRUE(lidar);
    EXPECT_EQ(lidar->header.stamp, stamp);
    EXPECT_EQ(lidar->header.frame_id, "lidar");
    expectFields(*lidar, {"x", "y", "z", "intensity"});
    EXPECT_TRUE(std::string(lidar->data.begin(), lidar->data.end()) ==
                readBytes(f.points("lidar")));

    // /tf: odom -> camera is the odomToCamera pose.
    const auto tf = topics["/tf"][i].instantiate<tf2_msgs::TFMessage>();
    ASSERT_TRUE(tf);
    ASSERT_EQ(tf->transforms.size(), 1u);
    const auto& t = tf->transforms[0];
    EXPECT_EQ(t.header.stamp, stamp);
    EXPECT_EQ(t.header.frame_id, "odom");
    EXPECT_EQ(t.child_frame_id, "camera_optical");
    const Eigen::Matrix4d pose = io::readVodPose(f.pose(), "odomToCamera");
    EXPECT_LT((toIsometry(t.transform).matrix() - pose).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(VodToBag, CompressedImagesKeepTheJpegBytesAndTheRangeAndPoseKeyApply) {
  const std::string root = sceneRoot();
  const std::string bag_path = ::testing::TempDir() + "vod_to_bag_compressed.bag";
  const auto r = runTool("--vod-root " + root + " --output " + bag_path +
                         " --compressed --frames 121-122 --pose-key mapToCamera --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  rosbag::Bag bag;
  BagContents contents = readBag(bag, bag_path);
  auto& topics = contents.by_topic;
  EXPECT_EQ(topics.count("/camera/image_raw"), 0u);
  ASSERT_EQ(topics["/camera/image_raw/compressed"].size(), 2u);
  EXPECT_EQ(topics["/camera/camera_info"].size(), 2u);
  ASSERT_EQ(topics["/tf"].size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const io::VodFrame f{root, 121 + i};
    const ros::Time stamp(1.0 + i / 10.0);  // defaults: start 1 s, 10 Hz, from the first frame
    const auto image =
        topics["/camera/image_raw/compressed"][i].instantiate<sensor_msgs::CompressedImage>();
    ASSERT_TRUE(image);
    EXPECT_EQ(image->header.stamp, stamp);
    EXPECT_NE(image->format.find("jpeg"), std::string::npos) << image->format;
    EXPECT_TRUE(std::string(image->data.begin(), image->data.end()) == readBytes(f.image()));
    const auto tf = topics["/tf"][i].instantiate<tf2_msgs::TFMessage>();
    ASSERT_TRUE(tf);
    EXPECT_EQ(tf->transforms[0].header.frame_id, "map");
    const Eigen::Matrix4d pose = io::readVodPose(f.pose(), "mapToCamera");
    EXPECT_LT((toIsometry(tf->transforms[0].transform).matrix() - pose).cwiseAbs().maxCoeff(),
              1e-6);
  }
}

TEST(VodToBag, AFrameWithoutASensorHasNoMessageForIt) {
  const std::string root = copyScene("missing");
  fs::remove(io::VodFrame{root, 121}.points("radar"));
  fs::remove(io::VodFrame{root, 122}.image());
  fs::remove(io::VodFrame{root, 120}.pose());
  const std::string bag_path = ::testing::TempDir() + "vod_to_bag_missing.bag";
  const auto r = runTool("--vod-root " + root + " --output " + bag_path + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  rosbag::Bag bag;
  BagContents contents = readBag(bag, bag_path);
  auto& topics = contents.by_topic;
  ASSERT_EQ(topics["/radar/points"].size(), 2u);
  EXPECT_EQ(topics["/radar/points"][0].getTime(), ros::Time(1.0));
  EXPECT_EQ(topics["/radar/points"][1].getTime(), ros::Time(1.2));
  EXPECT_EQ(topics["/camera/image_raw"].size(), 2u);
  EXPECT_EQ(topics["/camera/camera_info"].size(), 2u);
  ASSERT_EQ(topics["/tf"].size(), 2u);
  EXPECT_EQ(topics["/tf"][0].getTime(), ros::Time(1.1));
  EXPECT_EQ(topics["/lidar/points"].size(), 3u);
}

TEST(VodToBag, BadInputGivesAClearMessageAndNoBag) {
  const std::string no_tr = copyScene("no_tr");
  std::ofstream(io::VodFrame{no_tr, 121}.calib("radar"))
      << "P2: 149.5 0 96.1 0 0 149.5 62.5 0 0 0 1 0\n";
  const std::string bad_jpg = copyScene("bad_jpg");
  std::ofstream(io::VodFrame{bad_jpg, 122}.image(), std::ios::binary) << "not a jpeg at all";
  const std::string no_key = copyScene("no_key");
  std::ofstream(io::VodFrame{no_key, 121}.pose())
      << "{\"odomToCamera\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}\n";
  const std::string no_calib = copyScene("no_calib");
  fs::remove_all(no_calib + "/radar/training/calib");

  const std::string out = ::testing::TempDir() + "vod_to_bag_bad.bag";
  const struct {
    std::string args, expected;
    int code;
  } cases[] = {
      {"--vod-root " + no_tr, "Tr_velo_to_cam", 1},
      {"--vod-root " + bad_jpg, "00122.jpg: cannot decode image", 1},
      {"--vod-root " + no_key + " --pose-key mapToCamera", "'mapToCamera' not found", 1},
      {"--vod-root " + no_calib, "radar/training/calib", 1},
      {"--vod-root /nonexistent/vod", "no View-of-Delft frame", 1},
      {"--vod-root " + sceneRoot() + " --frames 500-600", "no View-of-Delft frame among the 101 selected", 1},
      {"--vod-root " + sceneRoot() + " --frames 9-3", "needs A <= B", 2},
      {"--vod-root " + sceneRoot() + " --rate 0", "--rate", 2},
      {"", "--vod-root", 2},
  };
  for (const auto& c : cases) {
    fs::remove(out);
    const auto r = runTool(c.args + " --output " + out + " --quiet");
    EXPECT_EQ(r.exit_code, c.code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.args << ": a failed conversion left a bag behind";
    EXPECT_FALSE(fs::exists(out + ".partial")) << c.args;
  }
}
