// Dataset layouts: View-of-Delft and KITTI object folders resolve a frame's files; KITTI
// calibration composed as the devkit projects.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "../../test_data.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace io = multimodal_nvs::io;

namespace {

std::string makeDirs(const std::string& path) {
  std::string partial;
  for (std::size_t i = 0; i <= path.size(); ++i) {
    if (i == path.size() || path[i] == '/') {
      if (!partial.empty()) ::mkdir(partial.c_str(), 0755);
    }
    if (i < path.size()) partial += path[i];
  }
  return path;
}

void touch(const std::string& path) {
  std::ofstream(path) << "x";
}

}  // namespace

TEST(DatasetLayout, ViewOfDelftNames) {
  const std::string root = makeDirs(::testing::TempDir() + "/layout_vod");
  makeDirs(root + "/lidar/training/image_2");
  std::remove((root + "/lidar/training/image_2/08350.png").c_str());  // from an earlier run
  const io::DatasetFrame frame{root, 8350};
  EXPECT_EQ(frame.layout(), io::DatasetLayout::kVod);
  EXPECT_EQ(frame.id(), "08350");
  EXPECT_EQ(frame.image(), root + "/lidar/training/image_2/08350.jpg");
  EXPECT_EQ(frame.points("radar"), root + "/radar/training/velodyne/08350.bin");
  EXPECT_EQ(frame.calib("lidar"), root + "/lidar/training/calib/08350.txt");
  EXPECT_EQ(frame.cameraInfo("lidar"), root + "/lidar/training/calib/08350_camera_info.yaml");
  EXPECT_EQ(frame.pose(), root + "/lidar/training/pose/08350.json");
  // A .png image where the .jpg is absent.
  touch(root + "/lidar/training/image_2/08350.png");
  EXPECT_EQ(frame.image(), root + "/lidar/training/image_2/08350.png");
}

TEST(DatasetLayout, KittiObjectNamesAtTheRootOrUnderTraining) {
  for (const std::string sub : {"", "/training"}) {
    const std::string root = ::testing::TempDir() + "/layout_kitti" + (sub.empty() ? "a" : "b");
    makeDirs(root + sub + "/image_2");
    makeDirs(root + sub + "/velodyne");
    const io::DatasetFrame frame{root, 100};
    EXPECT_EQ(frame.layout(), io::DatasetLayout::kKittiObject);
    EXPECT_EQ(frame.id(), "000100");
    EXPECT_EQ(frame.image(), root + sub + "/image_2/000100.png");
    EXPECT_EQ(frame.points("lidar"), root + sub + "/velodyne/000100.bin");
    EXPECT_EQ(frame.calib("lidar"), root + sub + "/calib/000100.txt");
    EXPECT_EQ(frame.points("radar"), "");  // KITTI has no radar
    EXPECT_EQ(frame.pose(), "");           // nor poses
  }
}

TEST(DatasetLayout, FrameNumbersUpToSixDigits) {
  EXPECT_EQ(io::parseFrameNumber("000105"), 105);
  EXPECT_EQ(io::parseFrameNumber("7480"), 7480);
  EXPECT_THROW(io::parseFrameNumber("1000000"), multimodal_nvs::InputError);
  EXPECT_THROW(io::parseFrameNumber("12a"), multimodal_nvs::InputError);
}

TEST(DatasetLayout, SharedKittiFolderIsDetected) {
  const std::string root = multimodal_nvs::test::dataDir() + "/kitti";
  MMNVS_REQUIRE_DATA(root);
  const io::DatasetFrame frame{root, 100};
  EXPECT_EQ(frame.layout(), io::DatasetLayout::kKittiObject);
  EXPECT_TRUE(io::fileExists(frame.image())) << frame.image();
  EXPECT_TRUE(io::fileExists(frame.points("lidar"))) << frame.points("lidar");
  EXPECT_TRUE(io::fileExists(frame.calib("lidar"))) << frame.calib("lidar");
  EXPECT_EQ(io::DatasetFrame({multimodal_nvs::test::dataDir() + "/vod", 8350}).layout(),
            io::DatasetLayout::kVod);
}

// KITTI's devkit: x_image = P2 · R0_rect · Tr_velo_to_cam · x. The composed extrinsic with K must
// give the same pixel as the three matrices.
TEST(KittiCalib, ComposesRectificationAndTheProjectionsTranslation) {
  const auto calib = io::parseKittiCalib(
      "P2: 721.5377 0 609.5593 44.85728 0 721.5377 172.854 0.2163791 0 0 1 0.002745884\n"
      "R0_rect: 0.9999239 0.00983776 -0.007445048 -0.009869795 0.9999421 -0.004278459 "
      "0.007402527 0.004351614 0.9999631\n"
      "Tr_velo_to_cam: 0.007533745 -0.9999714 -0.000616602 -0.004069766 0.01480249 0.0007280733 "
      "-0.9998902 -0.07631618 0.9998621 0.00752379 0.01480755 -0.2717806\n",
      "000100.txt");
  Eigen::Matrix<double, 3, 4> p2;
  p2 << 721.5377, 0, 609.5593, 44.85728, 0, 721.5377, 172.854, 0.2163791, 0, 0, 1, 0.002745884;
  Eigen::Matrix4d r0 = Eigen::Matrix4d::Identity();
  r0.topLeftCorner<3, 3>() << 0.9999239, 0.00983776, -0.007445048, -0.009869795, 0.9999421,
      -0.004278459, 0.007402527, 0.004351614, 0.9999631;
  Eigen::Matrix4d tr = Eigen::Matrix4d::Identity();
  tr.topRows<3>() = calib.matrix3x4("Tr_velo_to_cam");
  const Eigen::Vector4d x(20.0, 3.0, -1.0, 1.0);
  const Eigen::Vector3d devkit = p2 * r0 * tr * x;
  const Eigen::Vector3d camera = calib.sensorToCamera() * x;
  const Eigen::Vector3d ours = calib.intrinsics().matrix() * camera;
  EXPECT_NEAR(ours.x() / ours.z(), devkit.x() / devkit.z(), 1e-9);
  EXPECT_NEAR(ours.y() / ours.z(), devkit.y() / devkit.z(), 1e-9);
  EXPECT_NEAR(ours.z(), devkit.z(), 1e-9);
}

TEST(KittiCalib, ViewOfDelftStyleFilesKeepTheirExtrinsic) {
  const auto calib = io::parseKittiCalib(
      "P2: 1495.5 0 961.3 0 0 1495.4 624.9 0 0 0 1 0\nR0_rect: 1 0 0 0 1 0 0 0 1\n"
      "Tr_velo_to_cam: 0.1 -1 0.2 0.3 0.4 0.5 -1 0.6 1 0.7 0.8 0.9\n",
      "vod.txt");
  EXPECT_EQ(calib.sensorToCamera(), calib.matrix3x4("Tr_velo_to_cam"));  // bit for bit
}

// On the KITTI frames: how far the returns move in image 2 when R0_rect and P2's translation are
// used (the devkit's projection) against Tr_velo_to_cam alone with P2's K (what was done before).
TEST(KittiCalib, RectificationAndTranslationMoveTheReturns) {
  const std::string root = multimodal_nvs::test::dataDir() + "/kitti";
  MMNVS_REQUIRE_DATA(root + "/calib/000100.txt");
  std::vector<double> shifts;
  for (int number = 100; number <= 105; ++number) {
    const io::DatasetFrame frame{root, number};
    const auto calib = io::readKittiCalib(frame.calib("lidar"));
    const auto k = calib.intrinsics();
    const auto full = calib.sensorToCamera();
    const auto partial = calib.matrix3x4("Tr_velo_to_cam");
    const auto points = io::readPoints(frame.points("lidar"), io::PointFormat::kXyzi);
    for (const Eigen::Vector3f& p : points) {
      const Eigen::Vector4d x(p.x(), p.y(), p.z(), 1.0);
      const Eigen::Vector3d a = full * x, b = partial * x;
      if (!(a.z() > 1.0) || !(b.z() > 1.0)) continue;
      double ua = 0, va = 0, ub = 0, vb = 0;
      k.project(a.x(), a.y(), a.z(), &ua, &va);
      k.project(b.x(), b.y(), b.z(), &ub, &vb);
      if (ua < 0 || va < 0 || ua >= 1242 || va >= 375) continue;
      shifts.push_back(std::hypot(ua - ub, va - vb));
    }
  }
  ASSERT_GT(shifts.size(), 50000u);
  std::sort(shifts.begin(), shifts.end());
  const double median = shifts[shifts.size() / 2], most = shifts.back();
  std::cout << "[ kitti ] " << shifts.size() << " returns in image 2 over 000100-000105: with "
            << "R0_rect and P2's translation they move by median " << median << " px, max " << most
            << " px\n";
  EXPECT_GT(median, 3.0);  // ~0.6 degrees of rectification at 721 px per radian is ~7 px
}
