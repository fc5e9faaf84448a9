// The striped filters against the whole-image OpenCV calls, byte for byte: random float images
// with holes (as the `ipbasic` baseline sees them), several kernel shapes and sizes, image heights
// that do and do not split evenly, ROIs whose parent holds other values, 1, 2 and 5 threads.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/float_image_fixtures.hpp"
#include "multimodal_nvs/core/common/striped_filters.hpp"

namespace mm = multimodal_nvs;
using mm::test::expectSameBytes;
using mm::test::sparseFloatImage;

namespace {

const cv::Mat kKernels[] = {
    cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(3, 3)),
    cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)),
    cv::getStructuringElement(cv::MORPH_RECT, cv::Size(31, 31)),
    cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(7, 7)),
};

TEST(StripedFilters, DilateMatchesOpenCv) {
  for (int rows : {1, 7, 64, 97, 301}) {
    const cv::Mat image = sparseFloatImage(rows, 53, 0.9, 17u + rows);
    for (int threads : {1, 2, 5}) {
      mm::ThreadPool pool(threads);
      for (const cv::Mat& kernel : kKernels) {
        cv::Mat expected, actual;
        cv::dilate(image, expected, kernel);
        mm::stripedDilate(image, actual, kernel, pool);
        expectSameBytes(expected, actual);
      }
    }
  }
}

TEST(StripedFilters, RoiReadsItsParentLikeOpenCv) {
  const cv::Mat image = sparseFloatImage(260, 90, 0.8, 3u);
  const cv::Mat roi = image(cv::Rect(11, 40, 60, 170));
  mm::ThreadPool pool(2);
  for (const cv::Mat& kernel : kKernels) {
    cv::Mat expected, actual;
    cv::dilate(roi, expected, kernel);
    mm::stripedDilate(roi, actual, kernel, pool);
    expectSameBytes(expected, actual);
    // The parent's values reach into the ROI's result (the test would not see a stripe that
    // ignored them otherwise).
    cv::Mat isolated;
    cv::dilate(roi.clone(), isolated, kernel);
    EXPECT_GT(cv::norm(isolated, expected, cv::NORM_INF), 0.0);
  }
}

TEST(StripedFilters, MedianBlurMatchesOpenCv) {
  for (int rows : {1, 4, 33, 64, 97, 301}) {
    const cv::Mat image = sparseFloatImage(rows, 61, 0.5, 5u + rows);
    for (int ksize : {3, 5}) {
      for (int threads : {1, 2, 5}) {
        mm::ThreadPool pool(threads);
        cv::Mat expected, actual;
        cv::medianBlur(image, expected, ksize);
        mm::stripedMedianBlur(image, actual, ksize, pool);
        expectSameBytes(expected, actual);
      }
    }
  }
}

TEST(StripedFilters, MorphologyMatchesOpenCvWithIterations) {
  for (int rows : {1, 5, 50, 97, 400}) {
    const cv::Mat image = sparseFloatImage(rows, 47, 0.9, 23u + rows);
    for (int threads : {1, 2, 5}) {
      mm::ThreadPool pool(threads);
      for (int op : {cv::MORPH_DILATE, cv::MORPH_ERODE, cv::MORPH_OPEN, cv::MORPH_CLOSE}) {
        for (const cv::Mat& kernel : kKernels) {
          for (int iterations : {1, 3, 6}) {
            cv::Mat expected, actual;
            cv::morphologyEx(image, expected, op, kernel, cv::Point(-1, -1), iterations);
            mm::stripedMorphology(image, actual, op, kernel, iterations, pool);
            expectSameBytes(expected, actual);
          }
        }
      }
    }
  }
}

TEST(StripedFilters, OutputBufferIsReused) {
  const cv::Mat image = sparseFloatImage(200, 40, 0.7, 9u);
  mm::ThreadPool pool(2);
  cv::Mat out(200, 40, CV_32FC1);
  const uchar* before = out.data;
  mm::stripedMedianBlur(image, out, 5, pool);
  EXPECT_EQ(before, out.data);
  mm::stripedDilate(image, out, kKernels[0], pool);
  EXPECT_EQ(before, out.data);
}

}  // namespace
