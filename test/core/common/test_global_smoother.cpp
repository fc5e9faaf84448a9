// The weighted-least-squares smoother: the same solution as OpenCV's FastGlobalSmootherFilter (to
// float rounding: the pivots are multiplied by their reciprocal, 1e-4 of the values here),
// constants stay constant, and evidence does not cross an edge of the guide.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_filter.hpp>
#include <stdexcept>
#include <vector>

#include "multimodal_nvs/core/common/global_smoother.hpp"

namespace mm = multimodal_nvs;

namespace {
cv::Mat smoothGuide(int rows, int cols) {
  cv::Mat guide(rows, cols, CV_8UC3);
  cv::randu(guide, 0, 255);
  cv::GaussianBlur(guide, guide, cv::Size(0, 0), 2.0);
  return guide;
}
}  // namespace

TEST(GlobalSmoother, AgreesWithOpenCvsFastGlobalSmoother) {
  cv::setRNGSeed(3);
  // Odd sizes: partial row blocks and column chunks.
  const cv::Mat guide = smoothGuide(61, 203);
  cv::Mat evidence(guide.size(), CV_32FC3);
  cv::randu(evidence, 0.0, 1.0);
  mm::ThreadPool pool(2);
  for (int iterations : {1, 3}) {
    const mm::GlobalSmootherParams params{4000.0, 8.0, 0.25, iterations};
    cv::Mat reference;
    cv::ximgproc::createFastGlobalSmootherFilter(guide, params.lambda, params.sigma_color,
                                                 params.attenuation, params.iterations)
        ->filter(evidence, reference);
    std::vector<cv::Mat> planes;
    cv::split(evidence, planes);
    mm::smoothAlongGuide(guide, planes, params, pool);
    std::vector<cv::Mat> want;
    cv::split(reference, want);
    for (std::size_t p = 0; p < planes.size(); ++p) {
      for (int r = 0; r < guide.rows; ++r) {
        for (int c = 0; c < guide.cols; ++c) {
          ASSERT_NEAR(planes[p].at<float>(r, c), want[p].at<float>(r, c), 5e-5f)
              << "plane " << p << " at " << r << ", " << c << ", iterations " << iterations;
        }
      }
    }
  }
}

// Each plane is solved alone (the planes share only the coefficients): the same bits whether it is
// smoothed alone or with others, on one thread or two.
TEST(GlobalSmoother, APlaneGetsTheSameBitsAloneOrWithOthersOnAnyThreadCount) {
  cv::setRNGSeed(5);
  const cv::Mat guide = smoothGuide(45, 37);
  std::vector<cv::Mat> together(4);
  for (cv::Mat& plane : together) {
    plane.create(guide.size(), CV_32F);
    cv::randu(plane, 0.0, 1.0);
  }
  std::vector<cv::Mat> alone{together[2].clone()};
  mm::ThreadPool one(1), two(2);
  mm::smoothAlongGuide(guide, together, {}, two);
  mm::smoothAlongGuide(guide, alone, {}, one);
  EXPECT_EQ(cv::norm(alone[0], together[2], cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(alone[0], together[3], cv::NORM_INF), 0.0);
}

TEST(GlobalSmoother, ConstantStaysConstantAndOnePixelImagesWork) {
  mm::ThreadPool pool(2);
  const cv::Mat guide = smoothGuide(40, 70);
  std::vector<cv::Mat> planes{cv::Mat(guide.size(), CV_32F, cv::Scalar(2.5f))};
  mm::smoothAlongGuide(guide, planes, {}, pool);
  for (int r = 0; r < guide.rows; ++r)
    for (int c = 0; c < guide.cols; ++c)
      ASSERT_NEAR(planes[0].at<float>(r, c), 2.5f, 1e-4f) << r << ", " << c;
  const cv::Mat pixel(1, 1, CV_8UC3, cv::Scalar::all(9));
  std::vector<cv::Mat> one{cv::Mat(1, 1, CV_32F, cv::Scalar(4.0f))};
  mm::smoothAlongGuide(pixel, one, {}, pool);
  EXPECT_FLOAT_EQ(one[0].at<float>(0, 0), 4.0f);
}

TEST(GlobalSmoother, EvidenceSpreadsAlongItsSurfaceAndNotAcrossAnEdge) {
  mm::ThreadPool pool(2);
  cv::Mat guide(50, 100, CV_8UC3, cv::Scalar::all(40));
  guide.colRange(50, 100).setTo(cv::Scalar::all(200));
  std::vector<cv::Mat> planes{cv::Mat::zeros(guide.size(), CV_32F)};
  planes[0].at<float>(25, 10) = 1.0f;  // one sample on the dark half
  mm::smoothAlongGuide(guide, planes, {}, pool);
  const float same_surface = planes[0].at<float>(25, 45);
  const float across = planes[0].at<float>(25, 55);
  EXPECT_GT(same_surface, 0.0f);
  EXPECT_LT(across, 1e-3f * same_surface);
}

// Without vertical edges the column solves see no edge between rows (the result equals a uniform
// guide's where the guide changes only between rows), while the row solves still stop at an edge
// between columns.
TEST(GlobalSmoother, WithoutVerticalEdgesOnlyTheEdgesBetweenColumnsHold) {
  mm::ThreadPool pool(2);
  cv::Mat top_bottom(50, 100, CV_8UC3, cv::Scalar::all(40));
  top_bottom.rowRange(25, 50).setTo(cv::Scalar::all(200));
  const cv::Mat uniform(top_bottom.size(), CV_8UC3, cv::Scalar::all(40));
  const auto smoothed = [&](const cv::Mat& guide, bool vertical_edges, cv::Point sample) {
    std::vector<cv::Mat> planes{cv::Mat::zeros(guide.size(), CV_32F)};
    planes[0].at<float>(sample) = 1.0f;
    mm::GlobalSmootherParams params;
    params.vertical_edges = vertical_edges;
    mm::smoothAlongGuide(guide, planes, params, pool);
    return planes[0];
  };
  const cv::Point on_top(50, 10);  // (x, y)
  const cv::Mat with_edges = smoothed(top_bottom, true, on_top);
  const cv::Mat without = smoothed(top_bottom, false, on_top);
  EXPECT_LT(with_edges.at<float>(40, 50), 1e-3f * with_edges.at<float>(15, 50));
  EXPECT_EQ(cv::norm(without, smoothed(uniform, true, on_top), cv::NORM_INF), 0.0);

  cv::Mat left_right(50, 100, CV_8UC3, cv::Scalar::all(40));
  left_right.colRange(50, 100).setTo(cv::Scalar::all(200));
  const cv::Mat sideways = smoothed(left_right, false, cv::Point(10, 25));
  EXPECT_GT(sideways.at<float>(40, 45), 0.0f);  // down the same column band, past any row
  EXPECT_LT(sideways.at<float>(25, 55), 1e-3f * sideways.at<float>(25, 45));
}

TEST(GlobalSmoother, RejectsPlanesOfAnotherSizeOrType) {
  mm::ThreadPool pool(1);
  const cv::Mat guide = smoothGuide(10, 10);
  std::vector<cv::Mat> wrong_size{cv::Mat::zeros(9, 10, CV_32F)};
  EXPECT_THROW(mm::smoothAlongGuide(guide, wrong_size, {}, pool), std::invalid_argument);
  std::vector<cv::Mat> wrong_type{cv::Mat::zeros(10, 10, CV_64F)};
  EXPECT_THROW(mm::smoothAlongGuide(guide, wrong_type, {}, pool), std::invalid_argument);
  std::vector<cv::Mat> planes{cv::Mat::zeros(10, 10, CV_32F)};
  EXPECT_THROW(mm::smoothAlongGuide(cv::Mat(10, 10, CV_8UC1), planes, {}, pool),
               std::invalid_argument);
}
