// bilateralFilterFloat against a double-precision evaluation of the filter's definition (tight),
// against cv::bilateralFilter (within the error of OpenCV's interpolated weight table), its NaN
// rules, and its independence of the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <random>

#include "multimodal_nvs/core/common/bilateral_filter.hpp"

namespace mm = multimodal_nvs;

namespace {

/// Piecewise-constant patches of values in [1, 100) with a share `holes` of zeros and some noise:
/// the depth images the `ipbasic` baseline smooths.
cv::Mat patchImage(int rows, int cols, double holes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(1.0f, 100.0f), noise(-1.0f, 1.0f);
  std::bernoulli_distribution hole(holes), noisy(0.3);
  cv::Mat patches(rows / 4 + 1, cols / 4 + 1, CV_32FC1);
  for (int r = 0; r < patches.rows; ++r)
    for (int c = 0; c < patches.cols; ++c)
      patches.at<float>(r, c) = value(rng);
  cv::Mat image(rows, cols, CV_32FC1);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      float v = patches.at<float>(r / 4, c / 4);
      if (noisy(rng)) v += noise(rng);
      image.at<float>(r, c) = hole(rng) ? 0.0f : v;
    }
  }
  return image;
}

int reflect101(int i, int n) {
  return cv::borderInterpolate(i, n, cv::BORDER_REFLECT_101);
}

/// The filter's definition in double precision (OpenCV's neighbourhood, border and NaN rules).
double definition(const cv::Mat& in, int r, int c, int radius, double sigma_color,
                  double sigma_space) {
  const double centre = in.at<float>(r, c);
  double sum = 0, wsum = 0;
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      const double r2 = double(dy) * dy + double(dx) * dx;
      if (std::sqrt(r2) > radius || (dy == 0 && dx == 0)) continue;
      const double v = in.at<float>(reflect101(r + dy, in.rows), reflect101(c + dx, in.cols));
      if (std::isnan(v)) continue;
      const double d = std::isnan(centre) ? 0.0 : v - centre;
      const double w = std::exp(-r2 / (2 * sigma_space * sigma_space)) *
                       std::exp(-d * d / (2 * sigma_color * sigma_color));
      sum += w * v;
      wsum += w;
    }
  }
  return std::isnan(centre) ? sum / wsum : (sum + centre) / (wsum + 1);
}

}  // namespace

TEST(BilateralFilter, MatchesTheDefinition) {
  mm::ThreadPool pool(2);
  struct Case {
    int rows, cols, diameter;
    double sigma_color, sigma_space;
  };
  for (const Case& k :
       {Case{40, 37, 5, 1.5, 2.0}, Case{9, 64, 3, 4.0, 1.0}, Case{23, 50, 9, 10.0, 3.0},
        Case{3, 3, 5, 1.5, 2.0}, Case{1, 7, 5, 1.5, 2.0}, Case{6, 1, 5, 1.5, 2.0}}) {
    const cv::Mat in = patchImage(k.rows, k.cols, 0.2, 7u * k.rows + k.cols);
    cv::Mat out;
    mm::bilateralFilterFloat(in, out, k.diameter, k.sigma_color, k.sigma_space, pool);
    ASSERT_EQ(out.size(), in.size());
    ASSERT_EQ(out.type(), CV_32FC1);
    const int radius = k.diameter / 2;
    for (int r = 0; r < in.rows; ++r) {
      for (int c = 0; c < in.cols; ++c) {
        const double expected = definition(in, r, c, radius, k.sigma_color, k.sigma_space);
        ASSERT_NEAR(out.at<float>(r, c), expected, 2e-5 * std::max(1.0, std::abs(expected)))
            << k.rows << "x" << k.cols << " d=" << k.diameter << " at " << r << "," << c;
      }
    }
  }
}

TEST(BilateralFilter, AgreesWithOpenCvWithinItsWeightTable) {
  // OpenCV interpolates the range weight in a 4096-bin table over the image's value range: with
  // values spread over ~100 and sigma_color 1.5 a weight is off by up to ~3e-5, the output by up to
  // a few 1e-4 of the values. The filter here evaluates the weight itself.
  mm::ThreadPool pool(2);
  const cv::Mat in = patchImage(120, 136, 0.3, 11u);
  cv::Mat ours, theirs;
  mm::bilateralFilterFloat(in, ours, 5, 1.5, 2.0, pool);
  cv::bilateralFilter(in, theirs, 5, 1.5, 2.0);
  double worst = 0;
  for (int r = 0; r < in.rows; ++r)
    for (int c = 0; c < in.cols; ++c)
      worst = std::max(worst, double(std::abs(ours.at<float>(r, c) - theirs.at<float>(r, c))));
  EXPECT_LT(worst, 5e-3);
  EXPECT_GT(cv::norm(ours, in, cv::NORM_L1), 0.0);  // the filter did smooth
}

TEST(BilateralFilter, FollowsOpenCvNanRules) {
  mm::ThreadPool pool(1);
  cv::Mat in = patchImage(12, 16, 0.0, 3u);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  in.at<float>(5, 5) = nan;  // a NaN centre: its neighbours' average with spatial weights only
  in.at<float>(0, 0) = nan;  // in the corner: reflected neighbours too
  cv::Mat out;
  mm::bilateralFilterFloat(in, out, 5, 1.5, 2.0, pool);
  for (int r = 0; r < in.rows; ++r) {
    for (int c = 0; c < in.cols; ++c) {
      const float v = out.at<float>(r, c);
      ASSERT_TRUE(std::isfinite(v)) << r << "," << c;  // NaN neighbours are skipped
      EXPECT_NEAR(v, definition(in, r, c, 2, 1.5, 2.0), 1e-4) << r << "," << c;
    }
  }
}

TEST(BilateralFilter, ThreadCountDoesNotChangeTheBytes) {
  const cv::Mat in = patchImage(77, 93, 0.25, 5u);
  cv::Mat reference;
  {
    mm::ThreadPool pool(1);
    mm::bilateralFilterFloat(in, reference, 5, 1.5, 2.0, pool);
  }
  for (int threads : {2, 5}) {
    mm::ThreadPool pool(threads);
    cv::Mat out;
    mm::bilateralFilterFloat(in, out, 5, 1.5, 2.0, pool);
    for (int r = 0; r < in.rows; ++r)
      ASSERT_EQ(0, std::memcmp(reference.ptr(r), out.ptr(r), in.cols * sizeof(float)))
          << threads << " threads, row " << r;
  }
}

TEST(BilateralFilter, RejectsOtherTypesAndInPlace) {
  mm::ThreadPool pool(1);
  cv::Mat bytes(4, 4, CV_8UC1, cv::Scalar(1)), out;
  EXPECT_ANY_THROW(mm::bilateralFilterFloat(bytes, out, 5, 1.5, 2.0, pool));
  cv::Mat image = patchImage(4, 4, 0.0, 1u);
  EXPECT_ANY_THROW(mm::bilateralFilterFloat(image, image, 5, 1.5, 2.0, pool));
}
