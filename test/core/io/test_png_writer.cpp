// The PNG writer: what it writes decodes (OpenCV's libpng reader) to exactly the pixels given, at
// every compression level, for gray and BGR, odd sizes and Mats with padded rows; bad input throws.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/input_error.hpp"
#include "multimodal_nvs/core/io/png_writer.hpp"

namespace io = multimodal_nvs::io;
using multimodal_nvs::test::inputErrorOf;

namespace {

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "mmnvs_png_" + name;
}

cv::Mat randomImage(int rows, int cols, int type, int seed) {
  cv::Mat image(rows, cols, type);
  cv::RNG rng(seed);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

void expectRoundTrip(const cv::Mat& image, int level, const std::string& name) {
  const std::string path = tempPath(name);
  io::writePng(path, image, level);
  const cv::Mat back = cv::imread(path, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(back.empty()) << path << " did not decode";
  ASSERT_EQ(back.type(), image.type());
  ASSERT_EQ(back.size(), image.size());
  EXPECT_EQ(cv::norm(back, image, cv::NORM_INF), 0.0) << name << " level " << level;
}

}  // namespace

TEST(PngWriter, BgrAndGrayDecodeToTheSamePixelsAtEveryLevel) {
  const cv::Mat bgr = randomImage(37, 53, CV_8UC3, 1);
  const cv::Mat gray = randomImage(41, 29, CV_8UC1, 2);
  for (int level : {io::kPngStored, 1, 6, io::kPngMaxLevel}) {
    expectRoundTrip(bgr, level, "bgr.png");
    expectRoundTrip(gray, level, "gray.png");
  }
}

TEST(PngWriter, ChannelOrderIsBgrInAndRgbInTheFile) {
  // A pure-blue BGR pixel must come back blue (a swapped writer would decode it as red).
  cv::Mat blue(2, 3, CV_8UC3, cv::Scalar(255, 0, 0));
  expectRoundTrip(blue, io::kPngStored, "blue.png");
  EXPECT_EQ(cv::imread(tempPath("blue.png"), cv::IMREAD_UNCHANGED).at<cv::Vec3b>(1, 2),
            cv::Vec3b(255, 0, 0));
}

TEST(PngWriter, HonoursTheRowStepOfAView) {
  const cv::Mat big = randomImage(64, 80, CV_8UC3, 3);
  const cv::Mat view = big(cv::Rect(7, 5, 33, 21));  // rows padded by 47 pixels
  ASSERT_FALSE(view.isContinuous());
  expectRoundTrip(view, 1, "view.png");
  expectRoundTrip(cv::Mat(1, 1, CV_8UC1, cv::Scalar(200)), io::kPngStored, "one.png");
}

TEST(PngWriter, CompressionShrinksARegularImage) {
  cv::Mat mask(120, 160, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(20, 30, 60, 40)).setTo(255);
  io::writePng(tempPath("stored.png"), mask, io::kPngStored);
  io::writePng(tempPath("fast.png"), mask, 1);
  const auto size = [](const std::string& p) {
    return std::ifstream(p, std::ios::binary | std::ios::ate).tellg();
  };
  EXPECT_GT(size(tempPath("stored.png")), 120 * 161);  // every filtered row byte stored
  EXPECT_LT(size(tempPath("fast.png")) * 20, size(tempPath("stored.png")));
}

TEST(PngWriter, RejectsWhatItCannotWriteNamingTheFile) {
  const std::string path = tempPath("bad.png");
  EXPECT_NE(inputErrorOf([&] { io::writePng(path, cv::Mat()); }).find(path), std::string::npos);
  EXPECT_NE(inputErrorOf([&] { io::writePng(path, cv::Mat(4, 4, CV_16UC1)); }).find("8-bit"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([&] { io::writePng(path, cv::Mat(4, 4, CV_8UC4)); }).find("8-bit"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([&] { io::writePng(path, cv::Mat(4, 4, CV_8UC1), 13); }).find("level"),
            std::string::npos);
  const std::string missing = ::testing::TempDir() + "mmnvs_no_such_dir/x.png";
  EXPECT_NE(inputErrorOf([&] { io::writePng(missing, cv::Mat(4, 4, CV_8UC1)); }).find(missing),
            std::string::npos);
}
