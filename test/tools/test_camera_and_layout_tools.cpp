// The tools with a lens model and with both dataset layouts: a camera_info YAML's distortion is
// used or its unsupported model named, and KITTI object folders are read as users have them.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "test_data.hpp"
#include "tool_runner.hpp"

namespace io = multimodal_nvs::io;
using multimodal_nvs::test::runTool;

namespace {

std::string dir() {
  return ::testing::TempDir();
}

/// A 160x120 scene: calib, three points ahead, and a camera_info YAML of `model` with `d`.
void writeScene(const std::string& model, const std::string& d) {
  io::writeKittiCalib(
      dir() + "lens_calib.txt", {100, 100, 80, 60},
      (Eigen::Matrix<double, 3, 4>() << 0, -1, 0, 0, 0, 0, -1, 0, 1, 0, 0, 0).finished());
  io::writeFloatRecords(dir() + "lens_points.bin",
                        {10, 0, 0, 1, 0, 0, 0, 12, 1, 0.5, 1, 0, 0, 0, 8, -1, -0.5, 1, 0, 0, 0});
  std::ofstream(dir() + "lens_info.yaml")
      << "image_width: 160\nimage_height: 120\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
      << "  data: [100, 0, 80, 0, 100, 60, 0, 0, 1]\ndistortion_model: " << model
      << "\ndistortion_coefficients:\n  data: " << d << "\n";
}

/// The scene's command line with `camera_info` as its --camera-info.
std::string sceneArgs(const std::string& camera_info = dir() + "lens_info.yaml") {
  return "--points " + dir() + "lens_points.bin --calib " + dir() +
         "lens_calib.txt --camera-info " + camera_info + " --image-size 120 160 --model nearest";
}

}  // namespace

TEST(CameraInfoOption, PlumbBobRunsAndUnsupportedModelsAreNamed) {
  writeScene("plumb_bob", "[-0.1, 0.05, 0.0, 0.0, 0.0]");
  const auto ok = runTool("complete_depth", sceneArgs());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("\"points_in_view\": 3"), std::string::npos) << ok.output;

  writeScene("equidistant", "[0.1, 0.01, 0.0, 0.0]");
  const auto fisheye = runTool("complete_depth", sceneArgs());
  EXPECT_NE(fisheye.exit_code, 0);
  EXPECT_NE(fisheye.output.find("lens_info.yaml: distortion model 'equidistant' is not supported"),
            std::string::npos)
      << fisheye.output;

  writeScene("plumb_bob", "[-0.1, 0.05, 0.0]");
  const auto short_d = runTool("complete_depth", sceneArgs());
  EXPECT_NE(short_d.exit_code, 0);
  EXPECT_NE(short_d.output.find("needs 5 coefficients in D, got 3"), std::string::npos)
      << short_d.output;

  const auto missing =
      runTool("complete_depth", sceneArgs(dir() + "no_such.yaml"));
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("No such file or directory"), std::string::npos) << missing.output;
}

TEST(KittiLayout, CompleteDepthReadsTheKittiFolder) {
  const std::string root = multimodal_nvs::test::dataDir() + "/kitti";
  MMNVS_REQUIRE_DATA(root + "/image_2/000100.png");
  const auto lidar = runTool("complete_depth", "--vod-root " + root +
                                                   " --frame 100 --sensor lidar --model nearest "
                                                   "--stride 8 --threads 1");
  EXPECT_EQ(lidar.exit_code, 0) << lidar.output;
  EXPECT_NE(lidar.output.find("\"rows\": 47, \"cols\": 156"), std::string::npos) << lidar.output;
  const auto radar =
      runTool("complete_depth", "--vod-root " + root + " --frame 100 --sensor radar");
  EXPECT_NE(radar.exit_code, 0);
  EXPECT_NE(radar.output.find("KITTI object layout, which has no radar"), std::string::npos)
      << radar.output;
}

TEST(KittiLayout, EvaluateDepthOnKittiLidarOneInFour) {
  const std::string root = multimodal_nvs::test::dataDir() + "/kitti";
  MMNVS_REQUIRE_DATA(root + "/velodyne/000105.bin");
  const auto r = runTool("evaluate_depth", "--vod-root " + root +
                                               " --frames 100-101 --input lidar --subsample 4 "
                                               "--model linear --stride 4 --threads 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"mae\""), std::string::npos) << r.output;
}

TEST(DistortedLayout, CompleteDepthTakesTheFramesCameraInfo) {
  const std::string root = multimodal_nvs::test::dataDir() + "/distorted_camera";
  MMNVS_REQUIRE_DATA(root + "/lidar/training/calib/00000_camera_info.yaml");
  const auto with_lens = runTool("complete_depth", "--vod-root " + root +
                                                       " --frame 0 --sensor lidar --model nearest "
                                                       "--stride 8 --threads 1");
  EXPECT_EQ(with_lens.exit_code, 0) << with_lens.output;
}
