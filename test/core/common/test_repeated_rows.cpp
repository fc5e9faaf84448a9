// repeatedRowSources, and the filters that copy the output of repeated rows (median, bilateral)
// against computing every row: byte for byte.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/float_image_fixtures.hpp"
#include "multimodal_nvs/core/common/bilateral_filter.hpp"
#include "multimodal_nvs/core/common/repeated_rows.hpp"
#include "multimodal_nvs/core/common/striped_filters.hpp"

namespace mm = multimodal_nvs;
using mm::test::expectSameBytes;
using mm::test::sparseFloatImage;

namespace {

/// A depth image as IP-Basic leaves it above the highest ring: the first `repeated` rows are one
/// row; below them, and in a second block of `middle` equal rows, random values.
cv::Mat imageWithRepeatedRows(int rows, int cols, int repeated, int middle_at, int middle,
                              unsigned seed) {
  cv::Mat image = sparseFloatImage(rows, cols, 0.3, seed);
  for (int r = 1; r < repeated; ++r)
    image.row(0).copyTo(image.row(r));
  for (int r = middle_at + 1; r < middle_at + middle && r < rows; ++r)
    image.row(middle_at).copyTo(image.row(r));
  return image;
}

}  // namespace

TEST(RepeatedRows, SourcesFollowTheWindow) {
  mm::ThreadPool pool(2);
  // Rows: 0-5 equal (A), 6 different, 7-8 equal (B), 9-13 equal (C).
  cv::Mat image(14, 6, CV_32FC1);
  for (int r = 0; r < 14; ++r) {
    const float value = r <= 5 ? 1.0f : r == 6 ? 2.0f : r <= 8 ? 3.0f : 4.0f;
    image.row(r).setTo(value);
  }
  const std::vector<int> halo1 = mm::repeatedRowSources(image, 1, pool);
  // Halo 1: rows 1-4 have three equal rows around them (1 computed, 2-4 copy it); row 8 has 7-9,
  // which differ; rows 10-12 are C's interior (10 computed, 11-12 copy it); the last row never.
  const std::vector<int> expected1 = {0, 1, 1, 1, 1, 5, 6, 7, 8, 9, 10, 10, 10, 13};
  EXPECT_EQ(expected1, halo1);
  const std::vector<int> halo2 = mm::repeatedRowSources(image, 2, pool);
  const std::vector<int> expected2 = {0, 1, 2, 2, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13};
  EXPECT_EQ(expected2, halo2);
  // Halo 0 (a window of one row) and a single row copy nothing.
  const std::vector<int> halo0 = mm::repeatedRowSources(image, 0, pool);
  for (int r = 0; r < 14; ++r)
    EXPECT_EQ(r, halo0[r]);
  EXPECT_EQ(std::vector<int>{0}, mm::repeatedRowSources(image.rowRange(0, 1), 2, pool));
}

TEST(RepeatedRows, MedianBlurCopiesExactly) {
  for (int repeated : {0, 3, 5, 6, 40, 100}) {
    const cv::Mat in = imageWithRepeatedRows(100, 57, repeated, 60, 9, 31u + repeated);
    cv::Mat expected;
    cv::medianBlur(in, expected, 5);
    for (int threads : {1, 2, 5}) {
      mm::ThreadPool pool(threads);
      cv::Mat actual;
      mm::stripedMedianBlur(in, actual, 5, pool);
      expectSameBytes(expected, actual,
                      "repeated " + std::to_string(repeated) + ", " + std::to_string(threads));
    }
  }
}

TEST(RepeatedRows, BilateralCopiesExactly) {
  // A row's output depends only on its 5-row window: filtering the window alone computes it.
  mm::ThreadPool pool(2);
  const cv::Mat in = imageWithRepeatedRows(70, 45, 30, 45, 12, 5u);
  cv::Mat whole;
  mm::bilateralFilterFloat(in, whole, 5, 1.5, 2.0, pool);
  for (int r = 2; r + 2 < in.rows; ++r) {
    cv::Mat window = in.rowRange(r - 2, r + 3).clone(), alone;
    mm::bilateralFilterFloat(window, alone, 5, 1.5, 2.0, pool);
    expectSameBytes(alone.row(2), whole.row(r), "row " + std::to_string(r));
  }
}
