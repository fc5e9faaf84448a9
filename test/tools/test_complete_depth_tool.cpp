// The complete_depth tool on good and bad input: outputs loadable as the reference's layout, and
// every bad input gives a clear message and exit code 1 or 2, never a crash or a signal.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include "tool_runner.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>

#include "multimodal_nvs/core/io/kitti_calib.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/io/point_files.hpp"

namespace io = multimodal_nvs::io;

namespace {

using multimodal_nvs::test::ToolResult;
using RunResult = ToolResult;

ToolResult runTool(const std::string& args) {
  return multimodal_nvs::test::runTool("complete_depth", args);
}

std::string dir() {
  return ::testing::TempDir();
}

void writeScene() {
  io::writeKittiCalib(
      dir() + "cd_calib.txt", {100, 100, 80, 60},
      (Eigen::Matrix<double, 3, 4>() << 0, -1, 0, 0, 0, 0, -1, 0, 1, 0, 0, 0).finished());
  // Sensor frame x forward, y left, z up; 3 points ahead of the camera.
  io::writeFloatRecords(dir() + "cd_points.bin",
                        {10, 0, 0, 1, 0, 0, 0, 12, 1, 0.5, 1, 0, 0, 0, 8, -1, -0.5, 1, 0, 0, 0});
}

/// writeScene's three points as a binary_compressed PCD: fields stored one after another (all x,
/// then all y, then all z), LZF made of literal runs only (a control byte n - 1, then n <= 32
/// bytes), which every LZF decoder reads. `uncompressed` overrides the stored size word.
std::string compressedPcd(std::uint32_t uncompressed = 36) {
  const float xyz[3][3] = {{10, 12, 8}, {0, 1, -1}, {0, 0.5f, -0.5f}};
  const std::string raw(reinterpret_cast<const char*>(xyz), sizeof xyz);
  std::string lzf;
  for (std::size_t at = 0; at < raw.size(); at += 32) {
    const std::string run = raw.substr(at, 32);
    lzf += static_cast<char>(run.size() - 1) + run;
  }
  const std::uint32_t compressed = static_cast<std::uint32_t>(lzf.size());
  std::string pcd =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\n"
      "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA binary_compressed\n";
  pcd.append(reinterpret_cast<const char*>(&compressed), 4);
  pcd.append(reinterpret_cast<const char*>(&uncompressed), 4);
  return pcd + lzf;
}

}  // namespace

TEST(CompleteDepthTool, ABinaryCompressedPcdGivesTheSameDepthAsItsBin) {
  writeScene();
  std::ofstream(dir() + "cd_points.pcd", std::ios::binary) << compressedPcd();
  const std::string rest = " --calib " + dir() + "cd_calib.txt --image-size 120 160 --stride 2";
  const auto bin =
      runTool("--points " + dir() + "cd_points.bin" + rest + " --output " + dir() + "cd_from_bin");
  const auto pcd =
      runTool("--points " + dir() + "cd_points.pcd" + rest + " --output " + dir() + "cd_from_pcd");
  ASSERT_EQ(bin.exit_code, 0) << bin.output;
  ASSERT_EQ(pcd.exit_code, 0) << pcd.output;
  EXPECT_NE(pcd.output.find("\"points_in_view\": 3"), std::string::npos) << pcd.output;
  for (const char* array : {"_depth.npy", "_variance.npy", "_valid.npy"}) {
    EXPECT_EQ(io::readNpy(dir() + "cd_from_bin" + array).data,
              io::readNpy(dir() + "cd_from_pcd" + array).data)
        << array;
  }
  // A corrupt size word: exit 1, the file and the reason named.
  std::ofstream(dir() + "cd_corrupt.pcd", std::ios::binary) << compressedPcd(37);
  const auto bad = runTool("--points " + dir() + "cd_corrupt.pcd" + rest);
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find(dir() + "cd_corrupt.pcd: PCD binary_compressed data is corrupt"),
            std::string::npos)
      << bad.output;
}

TEST(CompleteDepthTool, WritesTheReferenceLayoutAndOneJsonLine) {
  writeScene();
  const auto r =
      runTool("--points " + dir() + "cd_points.bin --calib " + dir() +
              "cd_calib.txt --image-size 120 160 --stride 2 --png --output " + dir() + "cd_out");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"pixels\": 4800"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"points_in_view\": 3"), std::string::npos) << r.output;
  const auto depth = io::readNpy(dir() + "cd_out_depth.npy");
  EXPECT_EQ(depth.shape, (std::vector<std::size_t>{60, 80}));
  EXPECT_EQ(io::readNpy(dir() + "cd_out_valid.npy").dtype, "|u1");
  EXPECT_EQ(io::readNpy(dir() + "cd_out_variance.npy").dtype, "<f4");
  EXPECT_TRUE(std::ifstream(dir() + "cd_out_depth.png").good());
}

TEST(CompleteDepthTool, BadInputGivesAClearMessageAndNoCrash) {
  writeScene();
  const std::string calib = " --calib " + dir() + "cd_calib.txt";
  const std::string points = " --points " + dir() + "cd_points.bin";
  std::ofstream(dir() + "cd_trunc.bin", std::ios::binary) << std::string(30, '\0');
  std::ofstream(dir() + "cd_notr.txt") << "P2: 100 0 80 0 0 100 60 0 0 0 1 0\n";
  std::ofstream(dir() + "cd_nan.txt")
      << "P2: 100 0 80 0 0 abc 60 0 0 0 1 0\nTr_velo_to_cam: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  std::ofstream(dir() + "cd_f0.txt")
      << "P2: 0 0 80 0 0 100 60 0 0 0 1 0\nTr_velo_to_cam: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  const struct {
    std::string args, expected;
  } cases[] = {
      {" --points /nonexistent.bin" + calib + " --image-size 10 10", "cannot open"},
      {" --points " + dir() + "cd_trunc.bin" + calib + " --image-size 10 10", "not a multiple"},
      {points + " --calib " + dir() + "cd_notr.txt --image-size 10 10", "Tr_velo_to_cam"},
      {points + " --calib " + dir() + "cd_nan.txt --image-size 10 10", "unparsable"},
      {points + " --calib " + dir() + "cd_f0.txt --image-size 10 10", "focal length"},
      {points + calib, "--image-size"},
      {points + calib + " --image-size 10 10 --model magic", "unknown depth model"},
      {points + calib + " --image-size 10 10 --stride 0", "stride"},
      {points + calib + " --image-size 10 10 --bogus", "not expected"},
      {points + calib + " --image-size 10 10 --radius-deg abc", "not a number"},
  };
  for (const auto& c : cases) {
    const auto r = runTool(c.args);
    EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << c.args << " -> " << r.exit_code << "\n"
                                                      << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
  }
}

TEST(CompleteDepthTool, AScanWithNoUsablePointYieldsThePriorWithAWarning) {
  writeScene();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  io::writeFloatRecords(dir() + "cd_allnan.bin", {nan, 0, 0, 0, 0, 0, 0});
  const auto r = runTool("--points " + dir() + "cd_allnan.bin --calib " + dir() +
                         "cd_calib.txt --image-size 12 16 --output " + dir() + "cd_prior");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no usable point"), std::string::npos);
  const auto var = io::readNpy(dir() + "cd_prior_variance.npy").asFloat();
  for (float v : var)
    ASSERT_EQ(v, 625.0f);
}

// Without a pose the ground plane is --camera-height and --camera-pitch-deg (the node's
// ground_camera_height and ground_pitch_deg), reported on the stats line; a frame's pose wins.
TEST(CompleteDepthTool, WithoutAPoseTheGroundIsTheHeightAndPitchGivenAndAPoseWins) {
  writeScene();
  const std::string scan = "--points " + dir() + "cd_points.bin --calib " + dir() +
                           "cd_calib.txt --image-size 120 160 --model ground_gp --output " + dir();
  const auto level = runTool(scan + "cd_level");
  const auto pitched = runTool(scan + "cd_pitched --camera-height 1.6 --camera-pitch-deg 5");
  ASSERT_EQ(level.exit_code, 0) << level.output;
  ASSERT_EQ(pitched.exit_code, 0) << pitched.output;
  for (const char* field : {"\"ground_source\": \"parameters\"", "\"ground_camera_height\": 1.3,",
                            "\"ground_pitch_deg\": 0,"}) {
    EXPECT_NE(level.output.find(field), std::string::npos) << field << "\n" << level.output;
  }
  for (const char* field : {"\"ground_source\": \"parameters\"", "\"ground_camera_height\": 1.6,",
                            "\"ground_pitch_deg\": 5,", "\"ground_roll_deg\": 0,"}) {
    EXPECT_NE(pitched.output.find(field), std::string::npos) << field << "\n" << pitched.output;
  }
  EXPECT_NE(io::readNpy(dir() + "cd_level_depth.npy").data,
            io::readNpy(dir() + "cd_pitched_depth.npy").data);
  const auto steep = runTool(scan + "cd_steep --camera-pitch-deg 60");
  EXPECT_EQ(steep.exit_code, 2) << steep.output;
  EXPECT_NE(steep.output.find("--camera-pitch-deg"), std::string::npos) << steep.output;

  // A synthetic frame has a pose (a level camera 1.3 m up): it overrides the options.
  const std::string scene = dir() + "cd_pose_scene";
  const auto made = multimodal_nvs::test::runTool(
      "make_synthetic_scene", "--output " + scene + " --scale 0.1 --num-frames 1 --quiet");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const auto posed = runTool("--vod-root " + scene + " --frame 0 --model ground_gp --output " +
                             dir() + "cd_posed --camera-height 1.6 --camera-pitch-deg 5");
  ASSERT_EQ(posed.exit_code, 0) << posed.output;
  EXPECT_NE(posed.output.find("\"ground_source\": \"pose\""), std::string::npos) << posed.output;
  EXPECT_NE(posed.output.find("\"ground_camera_height\": 1.3"), std::string::npos) << posed.output;
  EXPECT_EQ(posed.output.find("\"ground_pitch_deg\": 5,"), std::string::npos) << posed.output;
  EXPECT_EQ(posed.output.find("guided_prior_weight"), std::string::npos) << posed.output;

  // image_guided also reports the returns' density and the prior weight that followed from it.
  const auto guided =
      runTool("--vod-root " + scene + " --frame 0 --model image_guided --output " + dir() +
              "cd_guided --guided-prior-weight 0.002 "
              "--guided-prior-reference-density 0.1");
  ASSERT_EQ(guided.exit_code, 0) << guided.output;
  const auto number_after = [&](const std::string& key) {
    const std::size_t at = guided.output.find("\"" + key + "\": ");
    return at == std::string::npos ? -1.0 : std::stod(guided.output.substr(at + key.size() + 4));
  };
  const double density = number_after("guided_return_density");
  EXPECT_GT(density, 0.0) << guided.output;
  EXPECT_NEAR(number_after("guided_prior_weight"), 0.002 * std::clamp(density / 0.1, 0.25, 10.0),
              1e-3 * 0.002)
      << guided.output;
  // The synthetic 3D radar leaves the image's top above its returns: the band's top is reported.
  EXPECT_NE(guided.output.find("\"guided_band_top_deg\": "), std::string::npos) << guided.output;
  const auto even = runTool("--vod-root " + scene + " --frame 0 --model image_guided --output " +
                            dir() + "cd_guided_even --guided-prior-weight-above-returns 1");
  ASSERT_EQ(even.exit_code, 0) << even.output;
  EXPECT_EQ(even.output.find("guided_band_top_deg"), std::string::npos) << even.output;
}

// Many frames in one process run as a pipeline (the next frame read while one is completed, the
// previous one written meanwhile): the outputs equal one-frame runs, and a bad frame in the middle
// ends the run with its file named after the frames before it are written, none after it.
TEST(CompleteDepthTool, FramesPipelineEqualsOneFrameRunsAndStopsAtABadFrame) {
  const std::string scene = dir() + "cd_frames_scene";
  const auto made = multimodal_nvs::test::runTool(
      "make_synthetic_scene", "--output " + scene + " --scale 0.1 --num-frames 4 --quiet");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const std::string model = " --model ground_gp --retain-percent 80";
  const auto all = runTool("--vod-root " + scene + " --frames 0-3 --quiet --output " + dir() +
                           "cd_frames_all" + model);
  ASSERT_EQ(all.exit_code, 0) << all.output;
  for (const std::string id : {"00000", "00003"}) {
    const auto one = runTool("--vod-root " + scene + " --frame " + id + " --output " + dir() +
                             "cd_frames_" + id + model);
    ASSERT_EQ(one.exit_code, 0) << one.output;
    for (const char* array : {"_depth.npy", "_variance.npy", "_valid.npy"}) {
      const auto a = io::readNpy(dir() + "cd_frames_all/" + id + array);
      const auto b = io::readNpy(dir() + "cd_frames_" + id + array);
      EXPECT_EQ(a.shape, b.shape);
      EXPECT_EQ(a.data, b.data) << id << array;
    }
  }
  // Frame 2's scan truncated to a size that is no whole number of records.
  const std::string bad = scene + "/radar/training/velodyne/00002.bin";
  std::ofstream(bad, std::ios::binary | std::ios::trunc) << std::string(30, '\0');
  const auto stopped = runTool("--vod-root " + scene + " --frames 0-3 --quiet --output " + dir() +
                               "cd_frames_bad" + model);
  EXPECT_EQ(stopped.exit_code, 1) << stopped.output;
  EXPECT_NE(stopped.output.find("00002.bin"), std::string::npos) << stopped.output;
  EXPECT_TRUE(std::ifstream(dir() + "cd_frames_bad/00001_depth.npy").good());
  EXPECT_FALSE(std::ifstream(dir() + "cd_frames_bad/00002_depth.npy").good());
  EXPECT_FALSE(std::ifstream(dir() + "cd_frames_bad/00003_depth.npy").good());
}
