// dilateSparseByDiamond against cv::dilate with the 3x3 cross iterated `radius` times, byte for
// byte: sparse non-negative images (a projected scan), returns at the image's edges, radius 0 to
// 9, a list with duplicates, zero pixels and out-of-range entries, and 1, 2 and 5 threads.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "core/float_image_fixtures.hpp"
#include "multimodal_nvs/core/common/sparse_dilation.hpp"

namespace mm = multimodal_nvs;
using mm::test::expectSameBytes;

namespace {

struct SparseScan {
  cv::Mat image;
  std::vector<long long> nonzero;
};

/// A share `density` of the pixels holds a value in (0, 100); the edges' corners hold one too.
SparseScan sparseScan(int rows, int cols, double density, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(0.5f, 100.0f);
  std::bernoulli_distribution occupied(density);
  SparseScan scan{cv::Mat(rows, cols, CV_32FC1, cv::Scalar(0)), {}};
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const bool corner = (r == 0 || r == rows - 1) && (c == 0 || c == cols - 1);
      if (!corner && !occupied(rng)) continue;
      scan.image.at<float>(r, c) = value(rng);
      scan.nonzero.push_back(static_cast<long long>(r) * cols + c);
    }
  }
  return scan;
}

}  // namespace

TEST(SparseDilation, MatchesTheIteratedCross) {
  const cv::Mat cross = cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(3, 3));
  struct Case {
    int rows, cols;
    double density;
  };
  for (const Case& k : {Case{70, 90, 0.01}, Case{64, 200, 0.05}, Case{9, 11, 0.3}, Case{1, 30, 0.1},
                        Case{25, 1, 0.1}}) {
    SparseScan scan = sparseScan(k.rows, k.cols, k.density, 13u * k.rows + k.cols);
    // Entries the function must ignore: a duplicate, an empty pixel, out of range.
    scan.nonzero.push_back(scan.nonzero.front());
    scan.nonzero.push_back(-1);
    scan.nonzero.push_back(static_cast<long long>(k.rows) * k.cols);
    for (int radius : {0, 1, 2, 6, 9}) {
      cv::Mat expected;
      if (radius == 0) {
        expected = scan.image.clone();
      } else {
        cv::dilate(scan.image, expected, cross, cv::Point(-1, -1), radius);
      }
      for (int threads : {1, 2, 5}) {
        mm::ThreadPool pool(threads);
        cv::Mat actual;
        mm::dilateSparseByDiamond(scan.image, scan.nonzero, radius, actual, pool);
        expectSameBytes(expected, actual,
                        std::to_string(k.rows) + "x" + std::to_string(k.cols) + " r" +
                            std::to_string(radius) + " t" + std::to_string(threads));
      }
    }
  }
}

TEST(SparseDilation, RejectsBadArguments) {
  mm::ThreadPool pool(1);
  cv::Mat out;
  cv::Mat bytes(4, 4, CV_8UC1, cv::Scalar(1));
  EXPECT_ANY_THROW(mm::dilateSparseByDiamond(bytes, {}, 1, out, pool));
  cv::Mat image(4, 4, CV_32FC1, cv::Scalar(0));
  EXPECT_ANY_THROW(mm::dilateSparseByDiamond(image, {}, -1, out, pool));
  EXPECT_ANY_THROW(mm::dilateSparseByDiamond(image, {}, 1, image, pool));
  cv::Mat wide(4, 8, CV_32FC1, cv::Scalar(0));
  EXPECT_ANY_THROW(mm::dilateSparseByDiamond(wide.colRange(0, 4), {}, 1, out, pool));
}
