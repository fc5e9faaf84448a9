// The sky mask's passes (strips, gradient at the walked pixels only, squares before hypot) decide
// every pixel exactly as the plain spelling does: OpenCV's gray image and 3x3 Sobel over the sky
// region, a walk down each column. Compared on structured random images of many shapes, with and
// without a pool, with gradient limits that fall exactly on a Sobel value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/sky_mask.hpp"

namespace mm = multimodal_nvs;

namespace {

/// The plain spelling: what skyMask computes, written with OpenCV's whole-image operations.
std::vector<std::uint8_t> plainSkyMask(const cv::Mat& guide, const std::vector<float>& prior,
                                       float far_depth, const std::vector<int>& top_return_row,
                                       double gradient, double brightness, double max_warmth) {
  const int rows = guide.rows, cols = guide.cols;
  std::vector<std::uint8_t> sky(std::size_t(rows) * cols, 0);
  cv::Mat gray, gx, gy;
  cv::cvtColor(guide, gray, cv::COLOR_BGR2GRAY);
  cv::Sobel(gray, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(gray, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  const float limit = static_cast<float>(gradient);
  for (int c = 0; c < cols; ++c) {
    for (int r = 0; r < std::min(rows, top_return_row[c]); ++r) {
      const std::size_t i = std::size_t(r) * cols + c;
      if (prior[i] < far_depth || gray.at<std::uint8_t>(r, c) < brightness) break;
      if (std::hypot(gx.at<float>(r, c), gy.at<float>(r, c)) > limit) break;
      const cv::Vec3b& bgr = guide.at<cv::Vec3b>(r, c);
      if (int(bgr[2]) - int(bgr[0]) > max_warmth) break;
      sky[i] = 1;
    }
  }
  return sky;
}

struct Case {
  cv::Mat guide;
  std::vector<float> prior;
  std::vector<int> top_return_row;
};

/// A bright, mostly smooth upper part (so that long sky runs exist) with noisy patches, warm
/// patches and edges; below each column's horizon a nearer prior; some columns with a return.
Case randomCase(int rows, int cols, std::mt19937& rng) {
  Case k;
  k.guide.create(rows, cols, CV_8UC3);
  std::uniform_int_distribution<int> noise(-3, 3), any(0, 255), coin(0, 9);
  const int base_b = 200 + coin(rng) * 5, base_r = 170 + coin(rng) * 6;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      cv::Vec3b& p = k.guide.at<cv::Vec3b>(r, c);
      const int ramp = (r * 7 + c * 3) / std::max(1, rows);
      p = cv::Vec3b(cv::saturate_cast<std::uint8_t>(base_b + noise(rng) - ramp),
                    cv::saturate_cast<std::uint8_t>(190 + noise(rng)),
                    cv::saturate_cast<std::uint8_t>(base_r + noise(rng) - ramp));
      if (coin(rng) == 0 && coin(rng) < 2) p = cv::Vec3b(any(rng), any(rng), any(rng));
    }
  }
  const int patches = 1 + (rows * cols) / 400;
  for (int i = 0; i < patches; ++i) {
    const int r0 = any(rng) % rows, c0 = any(rng) % cols;
    const cv::Rect box(c0, r0, std::min(cols - c0, 1 + coin(rng)),
                       std::min(rows - r0, 1 + coin(rng)));
    k.guide(box).setTo(cv::Scalar(any(rng), any(rng), any(rng)));
  }
  k.prior.assign(std::size_t(rows) * cols, 100.0f);
  k.top_return_row.assign(cols, rows);
  for (int c = 0; c < cols; ++c) {
    const int horizon = rows / 3 + (any(rng) % std::max(1, rows / 2 + 1));
    for (int r = horizon; r < rows; ++r)
      k.prior[std::size_t(r) * cols + c] = 10.0f + r;
    if (coin(rng) < 3) k.top_return_row[c] = any(rng) % (rows + 3);
    if (coin(rng) == 0) k.prior[std::size_t(any(rng) % rows) * cols + c] = NAN;
  }
  return k;
}

}  // namespace

TEST(SkyMask, DecidesEveryPixelAsThePlainSobelAndColumnWalk) {
  std::mt19937 rng(20261204);
  mm::ThreadPool two(2), three(3);
  const std::vector<cv::Size> sizes = {{1, 1}, {5, 1},  {1, 5},   {2, 2},    {3, 7},
                                       {7, 3}, {64, 9}, {65, 40}, {130, 37}, {200, 100}};
  // 12.5 = hypot(100, 0) / 8 and 0.125 = hypot(1, 0) / 8: limits that Sobel values hit exactly.
  const std::vector<double> gradients = {12.0, 12.5, 0.125, 7.3, 0.0, 200.0};
  int sky_pixels = 0, compared = 0;
  for (const cv::Size& size : sizes) {
    for (int repeat = 0; repeat < 3; ++repeat) {
      const Case k = randomCase(size.height, size.width, rng);
      for (const double gradient : gradients) {
        // Brightness and warmth limits between the 8-bit values too, and ones no pixel passes.
        for (const auto& [brightness, warmth] :
             std::vector<std::pair<double, double>>{{120, 10}, {120.5, 9.5}, {0, 255}, {300, 10}}) {
          const auto expected = plainSkyMask(k.guide, k.prior, 100.0f, k.top_return_row, gradient,
                                             brightness, warmth);
          for (mm::ThreadPool* pool : {static_cast<mm::ThreadPool*>(nullptr), &two, &three}) {
            const auto got = mm::skyMask(k.guide, k.prior, 100.0f, k.top_return_row, gradient,
                                         brightness, warmth, pool);
            ASSERT_EQ(got, expected) << size << " gradient " << gradient << " brightness "
                                     << brightness << " warmth " << warmth;
            ++compared;
          }
          sky_pixels += static_cast<int>(std::count(expected.begin(), expected.end(), 1));
        }
      }
    }
  }
  // The cases exercise both outcomes: long sky runs and runs cut by each test.
  EXPECT_EQ(compared, 10 * 3 * 6 * 4 * 3);
  EXPECT_GT(sky_pixels, 10000);
}

// The prior is asked for row by row, and only above the ground: a band of rows stops at its first
// row where every column has met a nearer prior (a caller need not compute the whole image of it).
// The mask is the same as with the prior as a plane.
TEST(SkyMask, ReadsThePriorOnlyDownToTheGround) {
  const int rows = 200, cols = 64, ground_row = 20;
  const cv::Mat guide(rows, cols, CV_8UC3, cv::Scalar(230, 220, 210));
  std::vector<float> prior(std::size_t(rows) * cols, 100.0f);
  for (int r = ground_row; r < rows; ++r)
    std::fill_n(prior.begin() + std::size_t(r) * cols, cols, 10.0f + 0.1f * r);
  const std::vector<int> no_return(cols, rows);
  std::vector<int> calls(rows, 0);
  const auto sky = mm::skyMask(
      guide,
      [&](int r, float* out) {
        ++calls[r];
        std::copy_n(prior.begin() + std::size_t(r) * cols, cols, out);
      },
      100.0f, no_return, 12.0, 120.0, 10.0);
  EXPECT_EQ(sky, mm::skyMask(guide, prior, 100.0f, no_return, 12.0, 120.0, 10.0));
  for (int r = 0; r < rows; ++r)
    EXPECT_EQ(sky[std::size_t(r) * cols], r < ground_row ? 1 : 0) << r;
  // Rows 0..20 of the first band of 32, then the first row of each band below it.
  int asked = 0;
  for (int r = 0; r < rows; ++r) {
    EXPECT_LE(calls[r], 1) << r;
    asked += calls[r];
  }
  EXPECT_EQ(asked, (ground_row + 1) + (rows - 1) / 32);
}
