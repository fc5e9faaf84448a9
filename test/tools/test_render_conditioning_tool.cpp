// End to end: the render_conditioning tool run as a process on tiny inputs the test writes itself
// (npy depth and mask, a PNG image, --intrinsics or VoD pose files). Good runs must write the
// documented folder (frames, masks, previews, cameras.json, metrics.json, the GEN3C arrays with
// their shapes and value sets); bad input must end with exit code 1 (input) or 2 (usage) and a
// message naming the problem, never a crash.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "multimodal_nvs/core/io/npy.hpp"

namespace io = multimodal_nvs::io;

namespace {

constexpr int kH = 120, kW = 160;
const char* const kIntrinsics = " --intrinsics 80 80 80 60";

struct RunResult {
  int exit_code;    // -1 when killed by a signal
  std::string out;  // stdout
  std::string all;  // stdout and stderr
};

std::string dir() {
  return ::testing::TempDir() + "rct_";
}

RunResult runTool(const std::string& args) {
  const std::string err_path = dir() + "stderr.txt";
  const std::string command =
      std::string(MMNVS_TOOL_DIR) + "/render_conditioning " + args + " 2>" + err_path;
  FILE* pipe = popen(command.c_str(), "r");
  std::string out;
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr)
    out += buffer.data();
  const int status = pclose(pipe);
  std::ifstream err_file(err_path);
  std::stringstream err;
  err << err_file.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, out + err.str()};
}

cv::Mat testImage() {
  cv::Mat image(kH, kW, CV_8UC3);
  cv::RNG rng(7);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

/// A smooth slanted plane 4..5 m away (no depth edge for the GEN3C filter), on an image-size grid
/// or a stride-2 grid; `zero` makes every pixel invalid.
void writeDepth(const std::string& path, int rows, int cols, bool zero = false) {
  std::vector<float> depth(static_cast<std::size_t>(rows) * cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      depth[static_cast<std::size_t>(r) * cols + c] = zero ? 0.0f : 4.0f + 1.0f * c / cols;
    }
  }
  io::writeNpy(path, depth.data(), {std::size_t(rows), std::size_t(cols)});
}

/// Kept mask: everything but a block (a hole the renderer must leave uncovered in frame 0).
void writeValid(const std::string& path, int rows, int cols, bool all_zero = false) {
  std::vector<std::uint8_t> valid(static_cast<std::size_t>(rows) * cols, all_zero ? 0 : 1);
  if (!all_zero) {
    for (int r = 20; r < 40; ++r) {
      for (int c = 30; c < 60; ++c)
        valid[static_cast<std::size_t>(r) * cols + c] = 0;
    }
  }
  io::writeNpy(path, valid.data(), {std::size_t(rows), std::size_t(cols)});
}

void writePose(const std::string& path, double x) {
  std::ofstream(path) << "{\"odomToCamera\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], "
                         "\"mapToCamera\": [1, 0, 0, "
                      << x << ", 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}\n";
}

void writeInputs() {
  cv::imwrite(dir() + "image.png", testImage());
  writeDepth(dir() + "depth.npy", kH, kW);
  writeDepth(dir() + "depth_s2.npy", kH / 2, kW / 2);
  writeDepth(dir() + "depth_zero.npy", kH, kW, true);
  writeDepth(dir() + "depth_odd.npy", 50, 70);
  writeValid(dir() + "valid.npy", kH, kW);
  writeValid(dir() + "valid_empty.npy", kH, kW, true);
  writeValid(dir() + "valid_small.npy", kH / 2, kW / 2);
  writePose(dir() + "pose0.json", 0.0);
  writePose(dir() + "pose1.json", 0.2);
  std::ofstream(dir() + "pose_bad.json") << "{\"mapToCamera\": [1, 0, 0]}\n";
  std::ofstream(dir() + "calib_f0.txt") << "P2: 0 0 80 0 0 80 60 0 0 0 1 0\n";
}

bool fileExists(const std::string& path) {
  return std::ifstream(path).good();
}

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<float> floats(const io::NpyArray& a) {
  return a.asFloat();
}

class RenderConditioningTool : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { writeInputs(); }
  const std::string common_ = " --image " + dir() + "image.png --depth " + dir() + "depth.npy";
};

}  // namespace

TEST_F(RenderConditioningTool, PresetWithGen3cExportWritesTheDocumentedFolder) {
  const std::string out = dir() + "out_preset";
  const RunResult r = runTool(common_ + " --valid " + dir() + "valid.npy" + kIntrinsics +
                              " --preset right --magnitude 0.2 --num-frames 4 --size 48 64"
                              " --splat zbuffer --gen3c --threads 1 --output " +
                              out);
  ASSERT_EQ(r.exit_code, 0) << r.all;
  // Exactly one line on stdout: the JSON summary.
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_EQ(r.out.front(), '{') << r.out;
  EXPECT_NE(r.out.find("\"frames\": 4"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"size\": [48, 64]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"splat\": \"zbuffer\""), std::string::npos) << r.out;

  for (int i = 0; i < 4; ++i) {
    char name[8];
    std::snprintf(name, sizeof name, "%03d", i);
    const cv::Mat frame = cv::imread(out + "/frames/" + name + ".png", cv::IMREAD_UNCHANGED);
    const cv::Mat mask = cv::imread(out + "/masks/" + name + ".png", cv::IMREAD_UNCHANGED);
    const cv::Mat preview = cv::imread(out + "/preview/" + name + ".jpg", cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(frame.empty() || mask.empty() || preview.empty()) << "frame " << i;
    EXPECT_EQ(frame.size(), cv::Size(64, 48));
    EXPECT_EQ(preview.size(), cv::Size(64, 48));
    ASSERT_EQ(mask.type(), CV_8UC1);
    EXPECT_EQ(cv::countNonZero(mask == 0) + cv::countNonZero(mask == 255), 48 * 64)
        << "mask values other than 0 and 255 in frame " << i;
  }
  EXPECT_TRUE(fileExists(out + "/cameras.json"));
  EXPECT_NE(readText(out + "/cameras.json").find("\"w2c\""), std::string::npos);

  const std::string g = out + "/gen3c/";
  const io::NpyArray images = io::readNpy(g + "rendered_warp_images.npy");
  const io::NpyArray masks = io::readNpy(g + "rendered_warp_masks.npy");
  EXPECT_EQ(images.dtype, "<f4");
  EXPECT_EQ(masks.dtype, "<f4");
  ASSERT_EQ(images.shape, (std::vector<std::size_t>{1, 4, 1, 3, 48, 64}));
  ASSERT_EQ(masks.shape, (std::vector<std::size_t>{1, 4, 1, 1, 48, 64}));
  const std::vector<float> rgb = floats(images), m = floats(masks);
  const std::size_t plane = 48 * 64;
  std::size_t holes = 0;
  for (std::size_t f = 0; f < 4; ++f) {
    for (std::size_t p = 0; p < plane; ++p) {
      const float mv = m[f * plane + p];
      ASSERT_TRUE(mv == 0.0f || mv == 1.0f) << "mask value " << mv;
      for (std::size_t c = 0; c < 3; ++c) {
        const float v = rgb[(f * 3 + c) * plane + p];
        ASSERT_TRUE(v >= -1.0f && v <= 1.0f) << v;
        if (mv == 0.0f) {
          ASSERT_EQ(v, -1.0f) << "hole not exactly -1";
        }
      }
      holes += mv == 0.0f;
    }
  }
  EXPECT_GT(holes, 0u) << "the kept-mask hole must stay a hole";
  EXPECT_LT(holes, 4 * plane / 2);
  EXPECT_TRUE(fileExists(g + "input_image.png"));
  EXPECT_NE(readText(g + "README.md").find("torch.from_numpy"), std::string::npos);
}

// The preview video is H.264 ('avc1' sample entry in the mp4, what browsers play) whenever this
// OpenCV can encode H.264, and at most 640 pixels wide with even sides.
TEST_F(RenderConditioningTool, PreviewVideoIsH264WhereTheEncoderExists) {
  const std::string probe = dir() + "probe_h264.mp4";
  const bool h264 =
      cv::VideoWriter(probe, cv::VideoWriter::fourcc('a', 'v', 'c', '1'), 10.0, cv::Size(64, 48))
          .isOpened();
  std::remove(probe.c_str());
  const std::string out = dir() + "out_video";
  const RunResult r = runTool(common_ + kIntrinsics +
                              " --preset right --magnitude 0.2 --num-frames 4 --size 48 1300"
                              " --threads 1 --quiet --output " +
                              out);
  ASSERT_EQ(r.exit_code, 0) << r.all;
  if (!h264)
    GTEST_SKIP() << "this OpenCV has no H.264 encoder (the tool fell back: " << r.all << ")";
  EXPECT_NE(r.out.find("\"video_codec\": \"avc1\""), std::string::npos) << r.out;
  const std::string mp4 = readText(out + "/preview.mp4");
  // ISO/IEC 14496-15: the visual sample entry of an H.264 track is the box type 'avc1'.
  EXPECT_NE(mp4.find("avc1"), std::string::npos) << "no avc1 sample entry";
  EXPECT_EQ(mp4.find("mp4v"), std::string::npos);
  cv::VideoCapture video(out + "/preview.mp4");
  ASSERT_TRUE(video.isOpened());
  EXPECT_EQ(video.get(cv::CAP_PROP_FRAME_WIDTH), 640);
  EXPECT_EQ(video.get(cv::CAP_PROP_FRAME_HEIGHT), 24);  // 48 * 640 / 1300 = 23.6 -> even 24
  EXPECT_EQ(video.get(cv::CAP_PROP_FRAME_COUNT), 4);
  const int fourcc = static_cast<int>(video.get(cv::CAP_PROP_FOURCC));
  const std::string name{char(fourcc & 255), char((fourcc >> 8) & 255), char((fourcc >> 16) & 255),
                         char((fourcc >> 24) & 255)};
  EXPECT_TRUE(name == "avc1" || name == "h264" || name == "H264") << name;
}

TEST_F(RenderConditioningTool, ReferenceFrameReproducesTheImageAtCoveredPixels) {
  // Render size = image size and gen3c: frame 0 is the reference view, so every covered pixel has
  // the input colour exactly and the kept-mask hole is a hole.
  const std::string out = dir() + "out_identity";
  const RunResult r = runTool(common_ + " --valid " + dir() + "valid.npy" + kIntrinsics +
                              " --preset forward --magnitude 0.5 --num-frames 2 --size 120 160"
                              " --splat gen3c --output " +
                              out);
  ASSERT_EQ(r.exit_code, 0) << r.all;
  const cv::Mat image = testImage();
  const cv::Mat frame = cv::imread(out + "/frames/000.png", cv::IMREAD_COLOR);
  const cv::Mat mask = cv::imread(out + "/masks/000.png", cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(frame.empty() || mask.empty());
  int covered = 0;
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const bool hole_in_input = v >= 20 && v < 40 && u >= 30 && u < 60;
      if (hole_in_input) {
        ASSERT_EQ(mask.at<std::uint8_t>(v, u), 0) << u << "," << v;
      } else if (mask.at<std::uint8_t>(v, u) == 255) {
        ASSERT_EQ(frame.at<cv::Vec3b>(v, u), image.at<cv::Vec3b>(v, u)) << u << "," << v;
        ++covered;
      }
    }
  }
  EXPECT_GT(covered, kH * kW * 8 / 10);
}

TEST_F(RenderConditioningTool, StrideGridDepthAndRecordedPosesWithGroundTruth) {
  // complete_depth --stride 2 output (60x80) with the full image; two recorded poses 0.2 m apart,
  // the image itself as ground truth of both.
  const std::string out = dir() + "out_recorded";
  const RunResult r =
      runTool(" --image " + dir() + "image.png --depth " + dir() + "depth_s2.npy" + kIntrinsics +
              " --poses " + dir() + "pose0.json " + dir() + "pose1.json --gt " + dir() +
              "image.png " + dir() + "image.png --num-frames 3 --size 60 80 --output " + out);
  ASSERT_EQ(r.exit_code, 0) << r.all;
  EXPECT_NE(r.out.find("\"depth_stride\": 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"gt_frames\": 2"), std::string::npos) << r.out;
  const std::string cameras = readText(out + "/cameras.json");
  EXPECT_NE(cameras.find("\"recorded_frames\": [0, 2]"), std::string::npos) << cameras;
  const std::string metrics = readText(out + "/metrics.json");
  EXPECT_NE(metrics.find("\"psnr\""), std::string::npos);
  EXPECT_NE(metrics.find("\"coverage\""), std::string::npos);
}

TEST_F(RenderConditioningTool, PngLevelChangesTheFileSizeNotThePixels) {
  // Frames are stored uncompressed by default (speed); --png-level compresses them. Both decode to
  // the same pixels, and the masks are compressed either way.
  const std::string args = common_ + " --valid " + dir() + "valid.npy" + kIntrinsics +
                           " --preset forward --magnitude 0.5 --num-frames 2 --size 120 160";
  const std::string stored = dir() + "out_png_stored", packed = dir() + "out_png_6";
  const RunResult a = runTool(args + " --output " + stored);
  ASSERT_EQ(a.exit_code, 0) << a.all;
  const RunResult b = runTool(args + " --png-level 6 --output " + packed);
  ASSERT_EQ(b.exit_code, 0) << b.all;
  const auto bytes = [](const std::string& path) {
    return static_cast<long>(std::ifstream(path, std::ios::binary | std::ios::ate).tellg());
  };
  for (const char* name : {"000", "001"}) {
    const std::string f = std::string("/frames/") + name + ".png";
    const std::string m = std::string("/masks/") + name + ".png";
    const cv::Mat frame_a = cv::imread(stored + f, cv::IMREAD_UNCHANGED);
    const cv::Mat frame_b = cv::imread(packed + f, cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(frame_a.empty() || frame_b.empty()) << name;
    EXPECT_EQ(cv::norm(frame_a, frame_b, cv::NORM_INF), 0.0) << name;
    EXPECT_GE(bytes(stored + f), 120L * (160 * 3 + 1)) << "default frames are stored";
    EXPECT_LT(bytes(packed + f), bytes(stored + f));
    EXPECT_LT(bytes(stored + m), 120L * 161 / 2) << "masks are compressed at the default too";
  }
  const RunResult bad = runTool(args + " --png-level 13 --output " + dir() + "out_png_bad");
  EXPECT_EQ(bad.exit_code, 2) << bad.all;
  EXPECT_NE(bad.all.find("--png-level"), std::string::npos) << bad.all;
}

TEST_F(RenderConditioningTool, BadInputGivesExitCodeAndAClearMessage) {
  const std::string preset = " --preset forward --magnitude 1 --num-frames 2 --size 24 32";
  const std::string out = " --output " + dir() + "out_bad";
  const struct {
    std::string args;
    int exit_code;
    std::string expected;
  } cases[] = {
      {common_ + kIntrinsics + preset, 2, "--output is required"},
      {" --image /nonexistent.png --depth " + dir() + "depth.npy" + kIntrinsics + preset + out, 1,
       "image not found"},
      {" --image " + dir() + "image.png --depth " + dir() + "depth_odd.npy" + kIntrinsics + preset +
           out,
       1, "neither the same size nor a complete_depth stride grid"},
      {common_ + " --valid " + dir() + "valid_small.npy" + kIntrinsics + preset + out, 1,
       "valid mask is 60x80"},
      {common_ + " --valid " + dir() + "valid_empty.npy" + kIntrinsics + preset + out, 1,
       "no kept pixel"},
      {" --image " + dir() + "image.png --depth " + dir() + "depth_zero.npy" + kIntrinsics +
           preset + out,
       1, "no kept pixel"},
      {common_ + " --intrinsics 0 80 80 60" + preset + out, 1, "focal length"},
      {common_ + " --calib " + dir() + "calib_f0.txt" + preset + out, 1, "calib_f0.txt"},
      {common_ + kIntrinsics + " --calib " + dir() + "calib_f0.txt" + preset + out, 2,
       "exactly one of --calib"},
      {common_ + kIntrinsics + " --preset sideways --magnitude 1 --size 24 32" + out, 1,
       "unknown trajectory preset 'sideways'"},
      {common_ + kIntrinsics + " --preset forward" + out, 2,
       "--preset and --magnitude go together"},
      {common_ + kIntrinsics + preset + " --size 0 32" + out, 2, "--size: must be >= 1"},
      {common_ + kIntrinsics + " --preset forward --magnitude 1 --num-frames 0" + out, 2,
       "--num-frames: must be >= 1"},
      {common_ + kIntrinsics + preset + " --splat fancy" + out, 1, "fancy"},
      {common_ + kIntrinsics + " --poses " + dir() + "pose0.json " + dir() + "pose_bad.json" +
           " --num-frames 2 --size 24 32" + out,
       1, "pose_bad.json"},
      {common_ + kIntrinsics + out, 2, "give exactly one trajectory"},
  };
  for (const auto& c : cases) {
    const RunResult r = runTool(c.args);
    EXPECT_EQ(r.exit_code, c.exit_code) << c.args << "\n" << r.all;
    EXPECT_NE(r.all.find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' for" << c.args << "\n"
        << r.all;
    EXPECT_EQ(r.all.find("Segmentation"), std::string::npos) << r.all;
  }
}

TEST_F(RenderConditioningTool, CamerasJsonRowsAreClosedArrays) {
  // cameras.json must be JSON: w2c is a list of four rows [a, b, c, d]. Frame 2 sits at the second
  // recorded pose: w2c = inv(T1) T0 moves points by -0.2 m in x.
  const std::string out = dir() + "out_cameras";
  const RunResult r = runTool(common_ + kIntrinsics + " --poses " + dir() + "pose0.json " + dir() +
                              "pose1.json --num-frames 3 --size 24 32 --output " + out);
  ASSERT_EQ(r.exit_code, 0) << r.all;
  const std::string cameras = readText(out + "/cameras.json");
  EXPECT_EQ(std::count(cameras.begin(), cameras.end(), '['),
            std::count(cameras.begin(), cameras.end(), ']'))
      << "unbalanced brackets:\n"
      << cameras;
  EXPECT_NE(cameras.find("\"w2c\": [[1, 0, 0, -0.2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]"),
            std::string::npos)
      << cameras;
}

TEST_F(RenderConditioningTool, StrideTwoDepthRendersAtALargerSize) {
  // complete_depth --stride 2 (60x80 for a 120x160 image) rendered at the image size, as VoD's
  // stride-2 depth (608x968) is at GEN3C's 704x1280: the frames must not come out empty.
  const std::string out = dir() + "out_upsampled";
  const RunResult r =
      runTool(" --image " + dir() + "image.png --depth " + dir() + "depth_s2.npy" + kIntrinsics +
              " --preset forward --magnitude 0.2 --num-frames 2 --size 120 160 --output " + out);
  ASSERT_EQ(r.exit_code, 0) << r.all;
  const cv::Mat mask = cv::imread(out + "/masks/000.png", cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(mask.empty());
  EXPECT_GT(cv::countNonZero(mask), kH * kW / 2) << "reference frame mostly holes";
}
