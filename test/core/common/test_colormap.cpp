#include <gtest/gtest.h>

#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>

#include "multimodal_nvs/core/common/colormap.hpp"
#include "multimodal_nvs/core/common/errors.hpp"

namespace mm = multimodal_nvs;

namespace {

cv::Vec3b openCvColour(int index, int colormap) {
  cv::Mat one(1, 1, CV_8UC1, cv::Scalar(index)), coloured;
  cv::applyColorMap(one, coloured, colormap);
  return coloured.at<cv::Vec3b>(0);
}

TEST(ColorScale, MapsTheRangeLinearlyOntoOpenCvsColourMap) {
  const mm::ColorScale scale(10.0, 20.0, cv::COLORMAP_VIRIDIS);
  EXPECT_EQ(scale(10.0f), openCvColour(0, cv::COLORMAP_VIRIDIS));
  EXPECT_EQ(scale(20.0f), openCvColour(255, cv::COLORMAP_VIRIDIS));
  EXPECT_EQ(scale(15.0f), openCvColour(128, cv::COLORMAP_VIRIDIS));  // 127.5 rounds up
  EXPECT_EQ(scale(12.0f), openCvColour(51, cv::COLORMAP_VIRIDIS));
}

TEST(ColorScale, ClampsOutsideTheRangeAndMarksNonFiniteValues) {
  const mm::ColorScale scale(0.0, 50.0, cv::COLORMAP_TURBO, cv::Vec3b(7, 8, 9));
  EXPECT_EQ(scale(-3.0f), scale(0.0f));
  EXPECT_EQ(scale(1e6f), scale(50.0f));
  EXPECT_EQ(scale(std::numeric_limits<float>::infinity()), cv::Vec3b(7, 8, 9));
  EXPECT_EQ(scale(-std::numeric_limits<float>::infinity()), cv::Vec3b(7, 8, 9));
  EXPECT_EQ(scale(std::numeric_limits<float>::quiet_NaN()), cv::Vec3b(7, 8, 9));
  EXPECT_EQ(scale.noData(), cv::Vec3b(7, 8, 9));
}

TEST(ColorScale, RejectsAnEmptyOrNonFiniteRange) {
  EXPECT_THROW(mm::ColorScale(5.0, 5.0), mm::InputError);
  EXPECT_THROW(mm::ColorScale(5.0, 1.0), mm::InputError);
  EXPECT_THROW(mm::ColorScale(0.0, std::numeric_limits<double>::infinity()), mm::InputError);
  EXPECT_THROW(mm::ColorScale(std::numeric_limits<double>::quiet_NaN(), 1.0), mm::InputError);
}

TEST(ColorizeWithScaleBar, DrawsHiddenPixelsGreyAndAppendsTheBar) {
  // At least 40 rows: the bar keeps a 20-pixel margin above and below.
  cv::Mat values(64, 96, CV_32FC1, cv::Scalar(2.0f));
  values.at<float>(1, 1) = std::numeric_limits<float>::quiet_NaN();
  cv::Mat valid(64, 96, CV_8UC1, cv::Scalar(1));
  valid.at<uchar>(2, 3) = 0;
  const cv::Mat canvas = mm::colorizeWithScaleBar(values, valid, 0.0, 4.0, "m");
  ASSERT_EQ(canvas.rows, 64);
  EXPECT_GT(canvas.cols, 96);
  EXPECT_EQ(canvas.at<cv::Vec3b>(1, 1), cv::Vec3b(40, 40, 40));
  EXPECT_EQ(canvas.at<cv::Vec3b>(2, 3), cv::Vec3b(40, 40, 40));
  EXPECT_EQ(canvas.at<cv::Vec3b>(0, 0), mm::ColorScale(0.0, 4.0, cv::COLORMAP_JET)(2.0f));
}

// A long label widens the margin instead of being cut at the image's edge, and an image too
// small for the usual margins still gets its bar.
TEST(ColorizeWithScaleBar, FitsLongLabelsAndTinyImages) {
  const std::string label = "standard deviation of the depth [m]";
  cv::Mat values(64, 96, CV_32FC1, cv::Scalar(2.0f));
  cv::Mat valid(64, 96, CV_8UC1, cv::Scalar(1));
  int baseline = 0;
  const int font_width = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, 0.35, 1, &baseline).width;
  EXPECT_GE(mm::colorizeWithScaleBar(values, valid, 0.0, 4.0, label).cols, 96 + font_width);
  cv::Mat tiny(6, 8, CV_32FC1, cv::Scalar(1.0f));
  cv::Mat tiny_valid(6, 8, CV_8UC1, cv::Scalar(1));
  const cv::Mat canvas = mm::colorizeWithScaleBar(tiny, tiny_valid, 0.0, 4.0, "m");
  EXPECT_EQ(canvas.rows, 6);
  EXPECT_GT(canvas.cols, 8);
}

}  // namespace
