// rectDilate / rectErode against cv::dilate / cv::erode with the same square kernel, byte for
// byte: sparse float images with holes (as the `ipbasic` baseline fills them), kernels smaller and
// larger than the image, ROIs whose parent holds other values (OpenCV reads them), in place, and
// 1, 2 and 5 threads.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/float_image_fixtures.hpp"
#include "multimodal_nvs/core/common/rect_morphology.hpp"

namespace mm = multimodal_nvs;
using mm::test::expectSameBytes;
using mm::test::sparseFloatImage;

namespace {

cv::Mat square(int ksize) {
  return cv::getStructuringElement(cv::MORPH_RECT, cv::Size(ksize, ksize));
}

}  // namespace

TEST(RectMorphology, MatchesOpenCvOnWholeImages) {
  struct Case {
    int rows, cols;
    double holes;
  };
  for (const Case& k : {Case{61, 97, 0.9}, Case{130, 300, 0.99}, Case{5, 7, 0.5}, Case{1, 40, 0.7},
                        Case{33, 1, 0.7}}) {
    const cv::Mat in = sparseFloatImage(k.rows, k.cols, k.holes, 17u * k.rows + k.cols);
    for (int ksize : {1, 3, 5, 13, 17, 31, 75}) {
      for (int threads : {1, 2, 5}) {
        mm::ThreadPool pool(threads);
        const std::string what = std::to_string(k.rows) + "x" + std::to_string(k.cols) + " k" +
                                 std::to_string(ksize) + " t" + std::to_string(threads);
        cv::Mat expected, actual;
        cv::dilate(in, expected, square(ksize));
        mm::rectDilate(in, actual, ksize, pool);
        expectSameBytes(expected, actual, "dilate " + what);
        cv::erode(in, expected, square(ksize));
        mm::rectErode(in, actual, ksize, pool);
        expectSameBytes(expected, actual, "erode " + what);
      }
    }
  }
}

TEST(RectMorphology, RoiReadsItsParentLikeOpenCv) {
  mm::ThreadPool pool(2);
  const cv::Mat parent = sparseFloatImage(90, 120, 0.95, 3u);
  // ROIs in the middle, at each edge and in a corner: the context available on each side differs.
  for (const cv::Rect& box :
       {cv::Rect(30, 20, 40, 30), cv::Rect(0, 10, 50, 60), cv::Rect(70, 0, 50, 45),
        cv::Rect(100, 80, 20, 10), cv::Rect(0, 0, 120, 90)}) {
    for (int ksize : {3, 17, 75}) {
      const std::string what = "box " + std::to_string(box.x) + "," + std::to_string(box.y) + " k" +
                               std::to_string(ksize);
      cv::Mat expected, actual;
      cv::dilate(parent(box), expected, square(ksize));
      mm::rectDilate(parent(box), actual, ksize, pool);
      expectSameBytes(expected, actual, "dilate " + what);
      cv::erode(parent(box), expected, square(ksize));
      mm::rectErode(parent(box), actual, ksize, pool);
      expectSameBytes(expected, actual, "erode " + what);
    }
  }
}

TEST(RectMorphology, InPlaceAndClosingLikeMorphologyEx) {
  mm::ThreadPool pool(2);
  const cv::Mat in = sparseFloatImage(80, 150, 0.9, 9u);
  cv::Mat expected;
  cv::morphologyEx(in, expected, cv::MORPH_CLOSE, square(13));
  cv::Mat work = in.clone();
  mm::rectDilate(work, work, 13, pool);
  mm::rectErode(work, work, 13, pool);
  expectSameBytes(expected, work, "closing in place");
}

TEST(RectMorphology, RejectsBadArguments) {
  mm::ThreadPool pool(1);
  cv::Mat bytes(4, 4, CV_8UC1, cv::Scalar(1)), out;
  EXPECT_ANY_THROW(mm::rectDilate(bytes, out, 3, pool));
  const cv::Mat image = sparseFloatImage(4, 4, 0.5, 1u);
  EXPECT_ANY_THROW(mm::rectDilate(image, out, 4, pool));
  EXPECT_ANY_THROW(mm::rectErode(image, out, 0, pool));
}
