#pragma once
// Float images for the tests of the image filters, and a byte-for-byte comparison of two images.
#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/core.hpp>
#include <random>
#include <string>

namespace multimodal_nvs {
namespace test {

/// Values in [1, 100) with a share `holes` of zeros: a depth image as the `ipbasic` baseline fills
/// it.
inline cv::Mat sparseFloatImage(int rows, int cols, double holes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(1.0f, 100.0f);
  std::bernoulli_distribution hole(holes);
  cv::Mat image(rows, cols, CV_32FC1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      image.at<float>(r, c) = hole(rng) ? 0.0f : value(rng);
  return image;
}

/// Fails (naming `what` and the first differing row) unless the two images have the same size,
/// type and bytes.
inline void expectSameBytes(const cv::Mat& expected, const cv::Mat& actual,
                            const std::string& what = "") {
  ASSERT_EQ(expected.size(), actual.size()) << what;
  ASSERT_EQ(expected.type(), actual.type()) << what;
  for (int r = 0; r < expected.rows; ++r) {
    ASSERT_EQ(0, std::memcmp(expected.ptr(r), actual.ptr(r), expected.cols * expected.elemSize()))
        << what << ", row " << r;
  }
}

}  // namespace test
}  // namespace multimodal_nvs
