// Back-projection of kept pixels and GEN3C's depth preprocessing (GEN3C's published renderer).
#include <gtest/gtest.h>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"

namespace mm = multimodal_nvs;

TEST(Backprojection, SampleImageOnGridTakesEveryStrideThPixel) {
  cv::Mat image(5, 7, CV_8UC3);
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 7; ++c)
      image.at<cv::Vec3b>(r, c) = {uchar(r), uchar(c), uchar(10 * r + c)};
  }
  const cv::Mat grid = mm::sampleImageOnGrid(image, {{5, 7}, 2});
  ASSERT_EQ(grid.rows, 3);  // ceil(5 / 2) x ceil(7 / 2)
  ASSERT_EQ(grid.cols, 4);
  ASSERT_EQ(grid.type(), CV_8UC3);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c)
      EXPECT_EQ(grid.at<cv::Vec3b>(r, c), image.at<cv::Vec3b>(2 * r, 2 * c)) << r << "," << c;
  }
  // Stride 1 is the image itself, not a copy.
  const cv::Mat same = mm::sampleImageOnGrid(image, {{5, 7}, 1});
  EXPECT_EQ(same.data, image.data);
  EXPECT_THROW(mm::sampleImageOnGrid(image, {{6, 7}, 2}), mm::InputError);
  EXPECT_THROW(mm::sampleImageOnGrid(cv::Mat(5, 7, CV_8UC1), {{5, 7}, 2}), mm::InputError);
}

TEST(Backprojection, LiftsKeptPixelsWithTheirColour) {
  const mm::PinholeIntrinsics k{50.0, 40.0, 3.0, 2.0};
  cv::Mat depth(4, 6, CV_32FC1, cv::Scalar(-1.0f));
  depth.at<float>(1, 5) = 10.0f;
  depth.at<float>(3, 0) = 2.0f;
  cv::Mat image(4, 6, CV_8UC3, cv::Scalar(0, 0, 0));
  image.at<cv::Vec3b>(1, 5) = {1, 2, 3};
  image.at<cv::Vec3b>(3, 0) = {200, 100, 50};
  const mm::ColoredCloud cloud = mm::backproject(depth, image, k);
  ASSERT_EQ(cloud.size(), 2u);
  // Row-major order; P = z K^-1 [u, v, 1].
  EXPECT_FLOAT_EQ(cloud.x[0], 10.0f * (5 - 3) / 50.0f);
  EXPECT_FLOAT_EQ(cloud.y[0], 10.0f * (1 - 2) / 40.0f);
  EXPECT_FLOAT_EQ(cloud.z[0], 10.0f);
  EXPECT_EQ(cloud.bgr[0], 1u | 2u << 8 | 3u << 16);
  EXPECT_FLOAT_EQ(cloud.x[1], 2.0f * (0 - 3) / 50.0f);
  EXPECT_EQ(cloud.bgr[1], 200u | 100u << 8 | 50u << 16);
  EXPECT_DOUBLE_EQ(cloud.medianDepth(), 10.0);
}

TEST(Backprojection, ScatterGoesToTheScaledPixelPosition) {
  cv::Mat depth(4, 8, CV_32FC1, cv::Scalar(0.0f));
  depth.at<float>(2, 6) = 5.0f;  // -> row round(2 * 0.5) = 1, col round(6 * 0.5) = 3
  depth.at<float>(3, 7) = 7.0f;  // -> row 2 (round half away), col 4 -> clamped to 3
  cv::Mat valid(4, 8, CV_8UC1, cv::Scalar(1));
  const cv::Mat out = mm::scatterDepthNearest(depth, valid, {2, 4});
  EXPECT_EQ(out.at<float>(1, 3), 7.0f);  // both land there; the later one in row-major order wins
  EXPECT_EQ(cv::countNonZero(out), 1);
  valid.at<std::uint8_t>(3, 7) = 0;
  EXPECT_EQ(mm::scatterDepthNearest(depth, valid, {2, 4}).at<float>(1, 3), 5.0f);
}

TEST(Backprojection, EdgeFilterDropsDepthSteps) {
  cv::Mat depth(12, 12, CV_32FC1, cv::Scalar(10.0f));
  depth.colRange(6, 12).setTo(20.0f);
  const cv::Mat reliable = mm::reliableDepthMask(depth, 0.05f, 5);
  // Within 2 columns of the step the 5x5 window sees both depths.
  for (int c = 0; c < 12; ++c) {
    const bool near_step = c >= 4 && c <= 7;
    EXPECT_EQ(reliable.at<std::uint8_t>(6, c), near_step ? 0 : 1) << c;
  }
  // A gentle slope (1% per pixel) survives.
  cv::Mat slope(12, 12, CV_32FC1);
  for (int c = 0; c < 12; ++c)
    slope.col(c).setTo(10.0f + 0.01f * c);
  EXPECT_EQ(
      cv::countNonZero(mm::reliableDepthMask(slope, 0.05f, 5).rowRange(2, 10).colRange(2, 10)), 64);
}

TEST(Backprojection, BuildCloudClampsResizesAndValidates) {
  const mm::PinholeIntrinsics k{20.0, 20.0, 4.0, 4.0};
  cv::Mat depth(8, 8, CV_32FC1, cv::Scalar(150.0f));
  cv::Mat image(8, 8, CV_8UC3, cv::Scalar(10, 20, 30));
  mm::BackprojectionParams p;
  p.resize_to_render = true;
  p.render_size = {4, 4};
  const mm::ColoredCloud cloud = mm::buildColoredCloud(depth, cv::Mat(), image, k, p);
  EXPECT_EQ(cloud.size(), 16u);
  EXPECT_FLOAT_EQ(cloud.z[0], 100.0f);  // clamped to GEN3C's 100 m
  EXPECT_DOUBLE_EQ(cloud.intrinsics.fx, 10.0);
  EXPECT_EQ(cloud.grid, (mm::ImageSize{4, 4}));

  EXPECT_THROW(mm::buildColoredCloud(depth, cv::Mat(), image(cv::Rect(0, 0, 7, 8)).clone(), k, p),
               mm::InputError);
  EXPECT_THROW(mm::buildColoredCloud(depth, cv::Mat::zeros(8, 8, CV_8UC1), image, k, p),
               mm::InputError);  // empty mask
  EXPECT_THROW(mm::buildColoredCloud(depth, cv::Mat::ones(4, 4, CV_8UC1), image, k, p),
               mm::InputError);
}
