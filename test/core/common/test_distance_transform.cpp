// exactDistanceTransform against OpenCV's precise transform, byte for byte, on random masks of
// several densities and shapes (sparse seeds like a projected LiDAR scan, a single seed, seeds only
// in one band of rows), for 1 and 2 threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <random>

#include "multimodal_nvs/core/common/distance_transform.hpp"
#include "multimodal_nvs/core/common/errors.hpp"

namespace mm = multimodal_nvs;

namespace {

/// 255 everywhere except zero pixels (the seeds) drawn with probability `density` in rows
/// [row0, rows).
cv::Mat randomMask(int rows, int cols, double density, int row0, unsigned seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution is_seed(density);
  cv::Mat mask(rows, cols, CV_8UC1, cv::Scalar(255));
  for (int r = row0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (is_seed(rng)) mask.at<std::uint8_t>(r, c) = 0;
  return mask;
}

void expectMatchesOpenCv(const cv::Mat& mask, int threads) {
  cv::Mat expected, actual, vertical;
  cv::distanceTransform(mask, expected, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  mm::ThreadPool pool(threads);
  mm::exactDistanceTransform(mask, actual, vertical, pool);
  ASSERT_EQ(actual.type(), CV_32FC1);
  ASSERT_EQ(actual.size(), mask.size());
  EXPECT_EQ(cv::norm(expected, actual, cv::NORM_INF), 0.0);
  EXPECT_EQ(0, std::memcmp(expected.data, actual.data, expected.total() * sizeof(float)));
}

}  // namespace

TEST(DistanceTransform, MatchesOpenCvPreciseOnSparseMasks) {
  for (int threads : {1, 2}) {
    expectMatchesOpenCv(randomMask(97, 131, 0.01, 0, 1), threads);
    expectMatchesOpenCv(randomMask(240, 320, 0.004, 120, 2), threads);  // seeds in the lower half
    expectMatchesOpenCv(randomMask(64, 200, 0.3, 0, 3), threads);
    expectMatchesOpenCv(randomMask(300, 17, 0.0005, 0, 4), threads);  // a seed or none per column
  }
}

TEST(DistanceTransform, SingleSeedGivesTheEuclideanDistance) {
  cv::Mat mask(50, 70, CV_8UC1, cv::Scalar(1));
  mask.at<std::uint8_t>(10, 60) = 0;
  cv::Mat distance, vertical;
  mm::ThreadPool pool(2);
  mm::exactDistanceTransform(mask, distance, vertical, pool);
  EXPECT_EQ(distance.at<float>(10, 60), 0.0f);
  EXPECT_EQ(distance.at<float>(13, 64), 5.0f);
  EXPECT_EQ(distance.at<float>(49, 0), std::sqrt(39.0f * 39.0f + 60.0f * 60.0f));
  expectMatchesOpenCv(mask, 1);
}

TEST(DistanceTransform, RejectsANonByteMask) {
  cv::Mat mask(4, 4, CV_32FC1, cv::Scalar(0)), distance, vertical;
  mm::ThreadPool pool(1);
  EXPECT_THROW(mm::exactDistanceTransform(mask, distance, vertical, pool), mm::InputError);
}
