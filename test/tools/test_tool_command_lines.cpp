// The command lines every tool shares (CLI11): --help layout, numbers checked with the option's
// name, `--name=value`, the one --frames syntax, and malformed pose JSON as a clear input error.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"
#include "tool_runner.hpp"

namespace io = multimodal_nvs::io;
using multimodal_nvs::test::runTool;

namespace {

const char* const kTools[] = {"complete_depth", "evaluate_depth", "render_conditioning",
                              "make_synthetic_scene"};

std::string dir() {
  return ::testing::TempDir();
}

/// A three-point scan and its calibration; returns the common arguments of complete_depth.
std::string completeDepthInput() {
  io::writeKittiCalib(
      dir() + "cl_calib.txt", {100, 100, 80, 60},
      (Eigen::Matrix<double, 3, 4>() << 0, -1, 0, 0, 0, 0, -1, 0, 1, 0, 0, 0).finished());
  io::writeFloatRecords(dir() + "cl_points.bin",
                        {10, 0, 0, 1, 0, 0, 0, 12, 1, 0.5, 1, 0, 0, 0, 8, -1, -0.5, 1, 0, 0, 0});
  return "--points " + dir() + "cl_points.bin --calib " + dir() + "cl_calib.txt ";
}

}  // namespace

TEST(ToolCommandLines, HelpListsRequiredInputsFirstWithDefaultsAndAnExample) {
  for (const char* tool : kTools) {
    const auto r = runTool(tool, "--help");
    ASSERT_EQ(r.exit_code, 0) << tool << "\n" << r.output;
    const std::size_t required = r.output.find("Required inputs:");
    ASSERT_NE(required, std::string::npos) << tool << "\n" << r.output;
    // No other option group before the required inputs.
    EXPECT_EQ(r.output.rfind(":\n  --", required), std::string::npos) << tool;
    EXPECT_NE(r.output.find("Example:\n  " + std::string(tool)), std::string::npos) << tool;
    EXPECT_NE(r.output.find("--threads INT:>=0=0"), std::string::npos) << tool << "\n" << r.output;
  }
  EXPECT_NE(runTool("complete_depth", "--help").output.find("--radius-deg FLOAT:>0=2"),
            std::string::npos);
  EXPECT_NE(runTool("render_conditioning", "--help").output.find("--pose-key TEXT=mapToCamera"),
            std::string::npos);
  EXPECT_NE(runTool("evaluate_depth", "--help").output.find("--pose-key TEXT=odomToCamera"),
            std::string::npos);
}

TEST(ToolCommandLines, MalformedNumbersAreUsageErrorsNamingTheOption) {
  const std::string in = completeDepthInput() + "--image-size 12 16 ";
  const struct {
    std::string args, expected;
  } cases[] = {
      {in + "--threads 4294967297", "--threads: '4294967297' is not a number of the option's type"},
      {in + "--threads -3", "--threads: must be >= 0, got -3"},
      {in + "--threads 2.5", "--threads"},
      {completeDepthInput() + "--image-size 20x 30abc", "--image-size: '20x' is not a number"},
      {completeDepthInput() + "--image-size 20", "--image-size"},
      {in + "--radius-deg nan", "--radius-deg: 'nan' is not a number"},
      {in + "--radius-deg inf", "--radius-deg: must be > 0, got inf"},
      {in + "--radius-deg 2m", "--radius-deg: '2m' is not a number"},
      {in + "--stride 0", "--stride: must be >= 1, got 0"},
      {in + "--sensor sonar", "--sensor"},
      {in + "--bogus 3", "not expected"},
      {in + "--model magic", "--model: unknown depth model 'magic'"},
  };
  for (const auto& c : cases) {
    const auto r = runTool("complete_depth", c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("(see --help)"), std::string::npos) << r.output;
  }
  const auto seed = runTool("make_synthetic_scene", "--output " + dir() + "cl_scene --seed -1");
  EXPECT_EQ(seed.exit_code, 2) << seed.output;
  EXPECT_NE(seed.output.find("--seed: must be >= 0"), std::string::npos) << seed.output;
  const auto count = runTool("make_synthetic_scene", "--output " + dir() + "cl_scene --frames 16");
  EXPECT_EQ(count.exit_code, 2) << count.output;
  EXPECT_NE(count.output.find("--num-frames"), std::string::npos) << count.output;
}

TEST(ToolCommandLines, EqualsFormIsAccepted) {
  const auto r = runTool("complete_depth",
                         completeDepthInput() + "--image-size 12 16 --radius-deg=3 --threads=1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"threads\": 1"), std::string::npos) << r.output;
}

TEST(ToolCommandLines, FramesListsAreRejectedAlikeInEveryTool) {
  // vod_to_bag (a ROS tool) shares the same parser; its own test covers its frame selection.
  for (const std::string tool : {"evaluate_depth", "render_conditioning"}) {
    const std::string rest =
        tool == "render_conditioning"
            ? " --image x.png --depth x.npy --output " + dir() + "cl_out" + " --intrinsics 1 1 1 1"
            : "";
    const auto r = runTool(tool, "--vod-root " + dir() + " --frames 5-3" + rest);
    EXPECT_EQ(r.exit_code, 2) << tool << "\n" << r.output;
    EXPECT_NE(r.output.find("--frames: range '5-3' needs A <= B"), std::string::npos)
        << tool << "\n"
        << r.output;
  }
}

TEST(ToolCommandLines, MalformedPoseJsonIsAnInputErrorWithThePosition) {
  const std::string in = completeDepthInput() + "--image-size 12 16 --model ground_gp ";
  std::ofstream(dir() + "cl_pose_bad.json") << "{\"odomToCamera\": [1, 0, 0, 0,\n 0, 1, 0 0]}\n";
  auto r = runTool("complete_depth", in + "--ground-pose " + dir() + "cl_pose_bad.json");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("cl_pose_bad.json:2:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("malformed pose JSON"), std::string::npos) << r.output;
  // A pose file without the default key (odometry) serves with its map pose; a key asked for by
  // name must be there.
  std::ofstream(dir() + "cl_pose_key.json")
      << "{\"mapToCamera\": [1, 0, 0, 5, 0, 0, 1, 7, 0, -1, 0, 1.5, 0, 0, 0, 1]}\n";
  r = runTool("complete_depth", in + "--ground-pose " + dir() + "cl_pose_key.json");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = runTool("complete_depth",
              in + "--ground-pose " + dir() + "cl_pose_key.json --pose-key utmToCamera");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("'utmToCamera' not found (keys present: mapToCamera)"),
            std::string::npos)
      << r.output;
  r = runTool("complete_depth", in + "--ground-pose /nonexistent/pose.json");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("cannot open pose file (No such file or directory)"), std::string::npos)
      << r.output;
}

TEST(ToolCommandLines, GroundGpRunsWithoutAPoseFile) {
  const auto r =
      runTool("complete_depth", completeDepthInput() + "--image-size 12 16 --model ground_gp");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"model\": \"ground_gp\""), std::string::npos) << r.output;
}

TEST(ToolCommandLines, CannotOpenErrorsCarryTheOsReason) {
  const auto r = runTool("complete_depth",
                         "--points /nonexistent.bin --calib /nonexistent.txt "
                         "--image-size 12 16");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("(No such file or directory)"), std::string::npos) << r.output;
}
