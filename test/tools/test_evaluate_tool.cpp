// The evaluate_depth tool end to end on a tiny generated VoD-layout scene (a wall at 10 m seen by a
// "radar" and a "LiDAR"), with exact dense ground truth, shards and LiDAR subsampling, and its
// errors on bad input.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include "tool_runner.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"

namespace io = multimodal_nvs::io;

namespace {

using multimodal_nvs::test::ToolResult;
using RunResult = ToolResult;

ToolResult runTool(const std::string& args) {
  return multimodal_nvs::test::runTool("evaluate_depth", args);
}

std::string root() {
  return ::testing::TempDir() + "ev_vod";
}

void makeDir(const std::string& path) {
  std::string partial;
  std::stringstream parts(path);
  std::string part;
  while (std::getline(parts, part, '/')) {
    partial += part + "/";
    ::mkdir(partial.c_str(), 0755);
  }
}

/// Frames 0 and 1: a wall 10 m ahead (sensor frame x forward, y left, z up), 60x80 image.
void writeScene(bool dense_truth) {
  const auto extrinsic =
      (Eigen::Matrix<double, 3, 4>() << 0, -1, 0, 0, 0, 0, -1, 0, 1, 0, 0, 0).finished();
  for (const char* sensor : {"radar", "lidar"}) {
    makeDir(root() + "/" + sensor + "/training/velodyne");
    makeDir(root() + "/" + sensor + "/training/calib");
  }
  for (int f = 0; f < 2; ++f) {
    char id[8];
    std::snprintf(id, sizeof id, "%05d", f);
    for (const char* sensor : {"radar", "lidar"}) {
      io::writeKittiCalib(root() + "/" + sensor + "/training/calib/" + id + ".txt",
                          {50, 50, 40, 30}, extrinsic);
    }
    std::vector<float> radar, lidar;
    for (int i = -3; i <= 3; ++i) {
      for (float v : {10.0f, 1.5f * i, 0.5f * (i % 2), 1.0f, 0.0f, 0.0f, 0.0f})
        radar.push_back(v);
    }
    for (float y = -7.5f; y <= 7.5f; y += 0.25f) {
      for (float z = -5.5f; z <= 5.5f; z += 0.5f) {
        for (float v : {10.0f, y, z, 1.0f})
          lidar.push_back(v);
      }
    }
    io::writeFloatRecords(root() + "/radar/training/velodyne/" + std::string(id) + ".bin", radar);
    io::writeFloatRecords(root() + "/lidar/training/velodyne/" + std::string(id) + ".bin", lidar);
    if (dense_truth) {
      makeDir(root() + "/depth_gt");
      std::vector<float> depth(60 * 80, 10.0f);
      for (int c = 0; c < 80; ++c)
        depth[c] = 0.0f;  // "sky" in the top row
      io::writeNpy(root() + "/depth_gt/" + id + ".npy", depth.data(), {60, 80});
    } else {
      std::remove((root() + "/depth_gt/" + id + ".npy").c_str());
    }
  }
}

std::string base() {
  return "--vod-root " + root() + " --image-size 60 80 ";
}

}  // namespace

TEST(EvaluateDepthTool, ExactOnAWallAgainstProjectedLidar) {
  writeScene(false);
  const std::string json = ::testing::TempDir() + "ev_out.json";
  const auto r =
      runTool(base() + "--frames 0-1 --model constant --retain-percent 100,50 --output " + json);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"frames\": 2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"mae\": 0,"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"delta1\": 1,"), std::string::npos) << r.output;
  std::ifstream in(json);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("\"gt\": \"lidar\""), std::string::npos);
  EXPECT_NE(text.str().find("\"retain_percent\": 50"), std::string::npos);
  EXPECT_NE(text.str().find("\"sums\""), std::string::npos);
}

TEST(EvaluateDepthTool, DenseTruthShardsAndLidarSubsampling) {
  writeScene(true);
  auto r = runTool(base() + "--frames 0,1 --model nearest --shard 1/2 --stride 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"frames\": 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"mae\": 0,"), std::string::npos) << r.output;
  // Dense truth: 30 x 40 grid minus the sky row.
  EXPECT_NE(r.output.find("\"gt_pixels\": 1160"), std::string::npos) << r.output;
  r = runTool(base() +
              "--frames 0 --input lidar --subsample 4 --subsample-phase 1 --gt lidar "
              "--model linear");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"mae\": 0,"), std::string::npos) << r.output;
}

TEST(EvaluateDepthTool, FramesWithoutAnImageRunTheModelsThatCanGoWithoutIt) {
  // The scene has no camera images (--image-size): ground_gp's colours are optional, image_guided
  // needs the image and says which file is missing.
  writeScene(false);
  auto r = runTool(base() + "--frames 0 --input lidar --subsample 4 --gt lidar --model ground_gp");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"frames\": 1"), std::string::npos) << r.output;
  r = runTool(base() + "--frames 0 --model image_guided");
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("image_2/00000.jpg: image not found"), std::string::npos) << r.output;
}

TEST(EvaluateDepthTool, EvaluatesSavedPredictions) {
  writeScene(true);
  std::vector<float> depth(60 * 80, 12.0f), variance(60 * 80, 1.0f);
  io::writeNpy(::testing::TempDir() + "ev_pred_depth.npy", depth.data(), {60, 80});
  auto r = runTool(base() + "--frames 0 --pred " + ::testing::TempDir() + "ev_pred");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"mae\": 2,"), std::string::npos) << r.output;
  r = runTool(base() + "--frames 0 --retain-percent 50 --pred " + ::testing::TempDir() + "ev_pred");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("variance"), std::string::npos) << r.output;
}

TEST(EvaluateDepthTool, SavedErrorsLineUpAcrossModelsWithNaNWhereNothingIsPredicted) {
  writeScene(true);
  // A saved prediction 2 m behind the wall, with a hole in row 10: its errors are +2 where it
  // predicts and NaN in the hole.
  std::vector<float> depth(60 * 80, 12.0f), variance(60 * 80, 1.0f);
  for (int c = 0; c < 80; ++c)
    depth[10 * 80 + c] = NAN;
  io::writeNpy(::testing::TempDir() + "ev_err_pred_depth.npy", depth.data(), {60, 80});
  io::writeNpy(::testing::TempDir() + "ev_err_pred_variance.npy", variance.data(), {60, 80});
  const std::string file_dir = ::testing::TempDir() + "ev_errors/file";
  const std::string model_dir = ::testing::TempDir() + "ev_errors/nearest";
  auto r = runTool(base() + "--frames 0 --pred " + ::testing::TempDir() + "ev_err_pred" +
                   " --save-errors " + file_dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = runTool(base() + "--frames 0 --model nearest --save-errors " + model_dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::NpyArray from_file = io::readNpy(file_dir + "/00000_errors.npy");
  const io::NpyArray from_model = io::readNpy(model_dir + "/00000_errors.npy");
  // One entry per ground-truth pixel (all but the top row), the same pixels for both.
  ASSERT_EQ(from_file.shape, std::vector<std::size_t>{60 * 80 - 80});
  ASSERT_EQ(from_model.shape, from_file.shape);
  const std::vector<float> file_errors = from_file.asFloat(), model_errors = from_model.asFloat();
  // Row 10 of the grid is entries 9 * 80 ... 10 * 80 - 1 (row 0 has no truth).
  for (std::size_t i = 0; i < file_errors.size(); ++i) {
    const bool hole = i >= 9 * 80 && i < 10 * 80;
    if (hole) {
      EXPECT_TRUE(std::isnan(file_errors[i])) << i;
    } else {
      EXPECT_FLOAT_EQ(file_errors[i], 2.0f) << i;
    }
    EXPECT_NEAR(model_errors[i], 0.0f, 1e-4f) << i;  // nearest on the wall: exact everywhere
  }
  // A directory that cannot be made: exit 1 naming it.
  r = runTool(base() + "--frames 0 --model nearest --save-errors /proc/no_such_dir/x");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("/proc/no_such_dir/x"), std::string::npos) << r.output;
}

TEST(EvaluateDepthTool, BadInputGivesAClearMessageAndNoCrash) {
  writeScene(false);
  const struct {
    std::string args, expected;
    int code;
  } cases[] = {
      {"--frames 0", "--vod-root", 2},
      {base(), "--frames", 2},
      {base() + "--frames 5-3", "A <= B", 2},
      {base() + "--frames 0 --shard 2/2", "--shard", 2},
      {base() + "--frames 0 --shard x", "--shard", 2},
      {base() + "--frames 0 --model magic", "unknown depth model", 2},
      {base() + "--frames 0 --input sonar", "--input", 2},
      {base() + "--frames 0 --retain-percent 120", "percentage", 2},
      {base() + "--frames 7", "cannot open", 1},
      {base() + "--frames 0 --gt dense", "not found", 1},
      {base() + "--frames 0 --input lidar", "--subsample", 2},
      {base() + "--frames 0 --subsample 2 --subsample-phase 2", "--subsample-phase", 2},
      {base() + "--frames 0,1 --pred /tmp/x", "one frame", 2},
      {"--vod-root " + root() + " --frames 0", "image not found", 1},
      {base() + "--frames-file /nonexistent.txt", "cannot open frame list", 1},
  };
  for (const auto& c : cases) {
    const auto r = runTool(c.args);
    EXPECT_EQ(r.exit_code, c.code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
  }
}
