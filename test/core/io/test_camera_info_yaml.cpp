// ROS camera_info YAML: the fields read, the errors of malformed files.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../input_error.hpp"
#include "multimodal_nvs/core/io/camera_info_yaml.hpp"

namespace io = multimodal_nvs::io;
using multimodal_nvs::test::inputErrorOf;

namespace {

std::string yaml(const std::string& model, const std::string& d, const std::string& extra = "") {
  return "image_width: 1920\nimage_height: 1200\ncamera_name: center_camera\n"
         "camera_matrix:\n  rows: 3\n  cols: 3\n"
         "  data: [2109.75, 0.0, 949.828, 0.0, 2071.72, 576.237, 0.0, 0.0, 1.0]\n"
         "distortion_model: " +
         model + "\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: " + d + "\n" + extra;
}

}  // namespace

TEST(CameraInfoYaml, ReadsSizeKAndDistortion) {
  const auto info = io::parseCameraInfoYaml(
      yaml("plumb_bob", "[-0.108, 0.139, -0.0038, -0.0048, 0.0]",
           "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"),
      "cam.yaml");
  EXPECT_EQ(info.size.width, 1920);
  EXPECT_EQ(info.size.height, 1200);
  EXPECT_DOUBLE_EQ(info.intrinsics.fx, 2109.75);
  EXPECT_DOUBLE_EQ(info.intrinsics.cy, 576.237);
  EXPECT_EQ(info.intrinsics.distortion.rosName(), "plumb_bob");
  EXPECT_DOUBLE_EQ(info.intrinsics.distortion.coefficients[3], -0.0048);
}

TEST(CameraInfoYaml, ZeroDistortionIsPinhole) {
  const auto info = io::parseCameraInfoYaml(yaml("plumb_bob", "[0, 0, 0, 0, 0]"), "c.yaml");
  EXPECT_FALSE(info.intrinsics.distortion.any());
}

TEST(CameraInfoYaml, ErrorsNameTheFileAndTheKey) {
  EXPECT_NE(inputErrorOf([] {
              io::parseCameraInfoYaml(yaml("equidistant", "[0.1, 0.2, 0.0, 0.0, 0.0]"), "e.yaml");
            }).find("e.yaml: distortion model 'equidistant' is not supported"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::parseCameraInfoYaml(yaml("plumb_bob", "[0.1, 0.2, 0.0, 0.0]"), "f.yaml");
            }).find("'distortion_coefficients' says 1x5 but has 4 numbers"),
            std::string::npos);
  // A size far outside int is reported as written (the fuzzer found the int conversion's UB).
  std::string huge_rows = yaml("plumb_bob", "[0, 0, 0, 0, 0]");
  huge_rows.replace(huge_rows.find("rows: 1"), 7, "rows: 2.2e17");
  EXPECT_NE(inputErrorOf([&] { io::parseCameraInfoYaml(huge_rows, "k.yaml"); })
                .find("'distortion_coefficients' says 2.2e+17x5 but has 5 numbers"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::parseCameraInfoYaml(yaml("plumb_bob", "[a, 0, 0, 0, 0]"), "g.yaml");
            }).find("not a finite number"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::parseCameraInfoYaml("image_width: [1\n", "h.yaml");
            }).find("h.yaml: not YAML"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { io::parseCameraInfoYaml("- 1\n- 2\n", "i.yaml"); }).find("no key"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::parseCameraInfoYaml("image_width: 10\n", "j.yaml");
            }).find("no 'image_height'"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::parseCameraInfoYaml(yaml("plumb_bob", "[0, 0, 0, 0, 0]",
                                           "rectification_matrix:\n  data: [1, 0, 0, 0, 0.9, 0.1, "
                                           "0, -0.1, 0.9]\n"),
                                      "k.yaml");
            }).find("'rectification_matrix' is not identity"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              io::readCameraInfoYaml("/nonexistent/cam.yaml");
            }).find("cannot open camera_info YAML (No such file or directory)"),
            std::string::npos);
}

TEST(CameraInfoYaml, FrameIntrinsicsChecksTheImageSize) {
  const std::string path = ::testing::TempDir() + "/frame_info.yaml";
  std::ofstream(path) << yaml("plumb_bob", "[-0.1, 0.1, 0.0, 0.0, 0.0]");
  const auto calib = io::parseKittiCalib("P2: 100 0 50 0 0 100 40 0 0 0 1 0\n", "c.txt");
  EXPECT_DOUBLE_EQ(io::frameIntrinsics(calib, "", {80, 100}).fx, 100.0);
  const auto k = io::frameIntrinsics(calib, path, {1200, 1920});
  EXPECT_DOUBLE_EQ(k.fx, 2109.75);
  EXPECT_TRUE(k.distortion.any());
  EXPECT_NE(inputErrorOf([&] {
              io::frameIntrinsics(calib, path, {600, 960});
            }).find("camera_info is 1920x1200 but the image is 960x600"),
            std::string::npos);
}
