// NVS metrics on known inputs (the paper's metric protocol).
#include <gtest/gtest.h>

#include <cmath>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/eval/image_metrics.hpp"

namespace mm = multimodal_nvs;

TEST(Metrics, PsnrOfKnownDifferences) {
  const cv::Mat a(20, 30, CV_8UC3, cv::Scalar(100, 100, 100));
  EXPECT_TRUE(std::isinf(mm::psnr(a, a)));
  // Every value differs by 5: MSE 25, PSNR = 10 log10(255^2 / 25).
  const cv::Mat b(20, 30, CV_8UC3, cv::Scalar(105, 95, 105));
  EXPECT_NEAR(mm::psnr(a, b), 10.0 * std::log10(255.0 * 255.0 / 25.0), 1e-12);
  // One channel differs by 30 on all pixels: MSE = 900 / 3 (mean over channels too).
  const cv::Mat c(20, 30, CV_8UC3, cv::Scalar(100, 100, 130));
  EXPECT_NEAR(mm::psnr(a, c), 10.0 * std::log10(255.0 * 255.0 / 300.0), 1e-12);
}

TEST(Metrics, SsimOfKnownInputs) {
  cv::Mat noise(32, 40, CV_8UC3);
  cv::RNG(7).fill(noise, cv::RNG::UNIFORM, 0, 256);
  EXPECT_NEAR(mm::ssim(noise, noise), 1.0, 1e-12);
  // Constant images: no variance, SSIM = (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1).
  const double c1 = (0.01 * 255) * (0.01 * 255);
  const cv::Mat x(32, 40, CV_8UC3, cv::Scalar(50, 50, 50));
  const cv::Mat y(32, 40, CV_8UC3, cv::Scalar(80, 80, 80));
  EXPECT_NEAR(mm::ssim(x, y), (2.0 * 50 * 80 + c1) / (50.0 * 50 + 80.0 * 80 + c1), 1e-9);
  // Per channel then averaged: only one channel differs.
  const cv::Mat z(32, 40, CV_8UC3, cv::Scalar(50, 50, 80));
  EXPECT_NEAR(mm::ssim(x, z), (2.0 + (2.0 * 50 * 80 + c1) / (50.0 * 50 + 80.0 * 80 + c1)) / 3.0,
              1e-9);
  // Inverted noise is strongly anti-correlated.
  EXPECT_LT(mm::ssim(noise, cv::Scalar::all(255) - noise), 0.0);
}

TEST(Metrics, CoveredPsnrAndCoverage) {
  const cv::Mat a(10, 10, CV_8UC3, cv::Scalar(0, 0, 0));
  cv::Mat b = a.clone();
  b.rowRange(0, 5).setTo(cv::Scalar(10, 10, 10));  // wrong only in the top half
  b.rowRange(5, 10).setTo(cv::Scalar(1, 1, 1));
  cv::Mat mask(10, 10, CV_8UC1, cv::Scalar(0));
  mask.rowRange(5, 10).setTo(255);
  EXPECT_NEAR(mm::coveredPsnr(a, b, mask), 10.0 * std::log10(255.0 * 255.0 / 1.0), 1e-12);
  EXPECT_DOUBLE_EQ(mm::coverage(mask), 0.5);
  EXPECT_TRUE(std::isnan(mm::coveredPsnr(a, b, cv::Mat::zeros(10, 10, CV_8UC1))));
}

TEST(Metrics, RejectsMismatchedImages) {
  const cv::Mat a(10, 10, CV_8UC3, cv::Scalar(0)), b(10, 11, CV_8UC3, cv::Scalar(0));
  EXPECT_THROW(mm::psnr(a, b), mm::InputError);
  EXPECT_THROW(mm::ssim(a, cv::Mat(10, 10, CV_8UC1, cv::Scalar(0))), mm::InputError);
  EXPECT_THROW(mm::psnr(a, cv::Mat(10, 10, CV_32FC3, cv::Scalar(0))), mm::InputError);
}
