#include "multimodal_nvs/core/eval/image_metrics.hpp"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace {

void requireComparable(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) throw InputError("metrics: empty image");
  if (a.depth() != CV_8U || b.depth() != CV_8U) throw InputError("metrics: images must be 8-bit");
  if (a.size() != b.size() || a.channels() != b.channels()) {
    throw InputError("metrics: images differ in size or channels (" + std::to_string(a.rows) + "x" +
                     std::to_string(a.cols) + "x" + std::to_string(a.channels()) + " vs " +
                     std::to_string(b.rows) + "x" + std::to_string(b.cols) + "x" +
                     std::to_string(b.channels()) + ")");
  }
}

double psnrFromMse(double mse) {
  if (mse <= 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

double ssimChannel(const cv::Mat& x8, const cv::Mat& y8) {
  constexpr int kWindow = 11;
  constexpr double kSigma = 1.5;
  constexpr double c1 = (0.01 * 255.0) * (0.01 * 255.0);
  constexpr double c2 = (0.03 * 255.0) * (0.03 * 255.0);
  cv::Mat x, y;
  x8.convertTo(x, CV_64F);
  y8.convertTo(y, CV_64F);
  const cv::Mat g = cv::getGaussianKernel(kWindow, kSigma, CV_64F);
  auto filter = [&](const cv::Mat& in) {
    cv::Mat out;
    // Border values never reach the cropped mean below, so the border mode is immaterial.
    cv::sepFilter2D(in, out, CV_64F, g, g, cv::Point(-1, -1), 0.0, cv::BORDER_REFLECT);
    return out;
  };
  const cv::Mat ux = filter(x), uy = filter(y);
  const cv::Mat uxx = filter(x.mul(x)), uyy = filter(y.mul(y)), uxy = filter(x.mul(y));
  const int pad = (kWindow - 1) / 2;
  if (x.rows <= 2 * pad || x.cols <= 2 * pad) {
    throw InputError("metrics: SSIM needs images larger than 10x10");
  }
  double total = 0.0;
  for (int r = pad; r < x.rows - pad; ++r) {
    for (int c = pad; c < x.cols - pad; ++c) {
      const double mx = ux.at<double>(r, c), my = uy.at<double>(r, c);
      const double vx = uxx.at<double>(r, c) - mx * mx;
      const double vy = uyy.at<double>(r, c) - my * my;
      const double vxy = uxy.at<double>(r, c) - mx * my;
      total +=
          ((2.0 * mx * my + c1) * (2.0 * vxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
    }
  }
  return total / (static_cast<double>(x.rows - 2 * pad) * (x.cols - 2 * pad));
}

}  // namespace

double psnr(const cv::Mat& a, const cv::Mat& b) {
  requireComparable(a, b);
  const double sse = cv::norm(a, b, cv::NORM_L2SQR);
  return psnrFromMse(sse / (static_cast<double>(a.total()) * a.channels()));
}

double ssim(const cv::Mat& a, const cv::Mat& b) {
  requireComparable(a, b);
  std::vector<cv::Mat> ca, cb;
  cv::split(a, ca);
  cv::split(b, cb);
  double sum = 0.0;
  for (std::size_t i = 0; i < ca.size(); ++i)
    sum += ssimChannel(ca[i], cb[i]);
  return sum / static_cast<double>(ca.size());
}

double coveredPsnr(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  requireComparable(a, b);
  if (mask.type() != CV_8UC1 || mask.size() != a.size()) {
    throw InputError("metrics: mask must be 8-bit, one channel, the size of the images");
  }
  const int covered = cv::countNonZero(mask);
  if (covered == 0) return std::numeric_limits<double>::quiet_NaN();
  const double sse = cv::norm(a, b, cv::NORM_L2SQR, mask);
  return psnrFromMse(sse / (static_cast<double>(covered) * a.channels()));
}

double coverage(const cv::Mat& mask) {
  if (mask.empty()) throw InputError("metrics: empty mask");
  return static_cast<double>(cv::countNonZero(mask)) / static_cast<double>(mask.total());
}

}  // namespace multimodal_nvs
