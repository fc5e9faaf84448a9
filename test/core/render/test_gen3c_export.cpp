// The GEN3C folder: shapes, dtypes, holes exactly -1, masks exactly {0, 1} (GEN3C's published
// renderer).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "../input_error.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/gen3c_export.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"

namespace mm = multimodal_nvs;

namespace {

std::string tempDir(const std::string& name) {
  return "/tmp/mmnvs_test_" + name + "_" + std::to_string(::getpid());
}

std::vector<float> floats(const mm::io::NpyArray& a) {
  std::vector<float> v(a.elementCount());
  std::memcpy(v.data(), a.data.data(), v.size() * sizeof(float));
  return v;
}

}  // namespace

TEST(Gen3cExport, RealLayoutShapes) {
  const mm::ImageSize size{mm::kGen3cHeight, mm::kGen3cWidth};
  EXPECT_EQ(mm::gen3cImagesShape(mm::kGen3cFrames, size),
            (std::vector<std::size_t>{1, 121, 1, 3, 704, 1280}));
  EXPECT_EQ(mm::gen3cMasksShape(mm::kGen3cFrames, size),
            (std::vector<std::size_t>{1, 121, 1, 1, 704, 1280}));
}

TEST(Gen3cExport, SmallExportRoundTrips) {
  const int frames = 3;
  const mm::ImageSize size{6, 8};
  const mm::PinholeIntrinsics k{8.0, 8.0, 3.5, 2.5};
  cv::Mat depth(size.height, size.width, CV_32FC1, cv::Scalar(4.0f));
  depth(cv::Rect(2, 1, 3, 3)).setTo(-1.0f);
  cv::Mat image(size.height, size.width, CV_8UC3);
  cv::RNG(3).fill(image, cv::RNG::UNIFORM, 0, 256);
  const mm::ColoredCloud cloud = mm::backproject(depth, image, k);
  mm::Trajectory traj;
  traj.size = size;
  for (int i = 0; i < frames; ++i) {
    Eigen::Matrix4d w2c = Eigen::Matrix4d::Identity();
    w2c(0, 3) = 0.3 * i;
    traj.cameras.push_back({w2c, k});
  }
  const std::string dir = tempDir("export");
  for (mm::SplatMode mode : {mm::SplatMode::kGen3c, mm::SplatMode::kZbuffer}) {
    mm::SplatParams params;
    params.mode = mode;
    mm::PointSplatter splatter(1);
    const auto rendered = splatter.render(cloud, traj, 0, frames, params);
    mm::Gen3cExportWriter writer(dir, frames, size);
    for (const auto& f : rendered)
      writer.append(f);
    writer.finish();
    mm::writeGen3cCompanions(dir, image, frames, size);

    const mm::io::NpyArray images = mm::io::readNpy(dir + "/rendered_warp_images.npy");
    const mm::io::NpyArray masks = mm::io::readNpy(dir + "/rendered_warp_masks.npy");
    EXPECT_EQ(images.dtype, "<f4");
    EXPECT_EQ(masks.dtype, "<f4");
    EXPECT_EQ(images.shape, (std::vector<std::size_t>{1, 3, 1, 3, 6, 8}));
    EXPECT_EQ(masks.shape, (std::vector<std::size_t>{1, 3, 1, 1, 6, 8}));
    const std::vector<float> img = floats(images), msk = floats(masks);
    const std::size_t plane = 6 * 8;
    int holes = 0;
    for (int f = 0; f < frames; ++f) {
      for (std::size_t p = 0; p < plane; ++p) {
        const float m = msk[f * plane + p];
        ASSERT_TRUE(m == 0.0f || m == 1.0f);
        for (int c = 0; c < 3; ++c) {
          const float v = img[(f * 3 + c) * plane + p];
          if (m == 0.0f) {
            ASSERT_EQ(v, -1.0f);
          } else {
            ASSERT_GE(v, -1.0f);
            ASSERT_LE(v, 1.0f);
          }
        }
        holes += m == 0.0f;
      }
    }
    EXPECT_GE(holes, 9 * frames);
    // Frame 0 is the reference view: plane 0 is red, i.e. OpenCV channel 2.
    EXPECT_FLOAT_EQ(img[0], image.at<cv::Vec3b>(0, 0)[2] / 127.5f - 1.0f);
    EXPECT_FLOAT_EQ(img[2 * plane], image.at<cv::Vec3b>(0, 0)[0] / 127.5f - 1.0f);
  }
  std::ifstream readme(dir + "/README.md");
  std::stringstream text;
  text << readme.rdbuf();
  EXPECT_NE(text.str().find("torch.from_numpy(np.load("), std::string::npos);
  EXPECT_EQ(cv::imread(dir + "/input_image.png").size(), cv::Size(8, 6));
}

TEST(Gen3cExport, CountAndSizeMismatchesAreErrors) {
  const std::string dir = tempDir("mismatch");
  mm::RenderedFrame frame;
  frame.bgr = cv::Mat::zeros(4, 5, CV_8UC3);
  frame.mask = cv::Mat::zeros(4, 5, CV_8UC1);
  mm::Gen3cExportWriter short_writer(dir, 2, {4, 5});
  short_writer.append(frame);
  EXPECT_THROW(short_writer.finish(), mm::InputError);
  // A frame in the middle never written (the workers write by index).
  mm::Gen3cExportWriter gap(dir, 3, {4, 5});
  gap.write(0, frame);
  gap.write(2, frame);
  EXPECT_NE(mm::test::inputErrorOf([&] { gap.finish(); }).find("2 frames written"),
            std::string::npos);
  mm::Gen3cExportWriter wrong_size(dir, 1, {4, 6});
  EXPECT_THROW(wrong_size.append(frame), mm::InputError);
}

TEST(Gen3cExport, FramesWrittenFromThreadsInAnyOrderGiveTheSameBytes) {
  const int frames = 6;
  const mm::ImageSize size{5, 7};
  std::vector<mm::RenderedFrame> rendered(frames);
  cv::RNG rng(11);
  for (mm::RenderedFrame& f : rendered) {
    f.bgr.create(size.height, size.width, CV_8UC3);
    f.mask.create(size.height, size.width, CV_8UC1);
    rng.fill(f.bgr, cv::RNG::UNIFORM, 0, 256);
    rng.fill(f.mask, cv::RNG::UNIFORM, 0, 2);
  }
  const auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string in_order = tempDir("in_order"), shuffled = tempDir("shuffled");
  {
    mm::Gen3cExportWriter writer(in_order, frames, size);
    for (const mm::RenderedFrame& f : rendered)
      writer.append(f);
    writer.finish();
  }
  {
    mm::Gen3cExportWriter writer(shuffled, frames, size);
    // Two threads, each from the back: odd frames on one, even frames on the other.
    std::thread odd([&] {
      for (int i = frames - 1; i >= 0; i -= 2)
        writer.write(i, rendered[i]);
    });
    for (int i = frames - 2; i >= 0; i -= 2)
      writer.write(i, rendered[i]);
    odd.join();
    EXPECT_THROW(writer.write(3, rendered[3]), mm::InputError);  // each index once
    EXPECT_THROW(writer.write(frames, rendered[0]), mm::InputError);
    writer.finish();
  }
  for (const char* name : {"/rendered_warp_images.npy", "/rendered_warp_masks.npy"}) {
    const std::string a = bytes(in_order + name), b = bytes(shuffled + name);
    EXPECT_GT(a.size(), 5u * 7u * frames * sizeof(float));
    EXPECT_EQ(a, b) << name;
  }
}
