#pragma once
// Colour maps for showing depth and uncertainty to people: a fixed-range scale (the nodelet's
// colour images) and a labelled scale bar (the tools' PNGs).
#include <array>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

namespace multimodal_nvs {

/// A linear value -> colour map over [vmin, vmax] with one of OpenCV's colour maps (256 colours).
/// Values outside the range take the end colours; non-finite values take `no_data`. BGR order, as
/// OpenCV (and the bgr8 image encoding) has it.
class ColorScale {
 public:
  ColorScale(double vmin, double vmax, int colormap = cv::COLORMAP_TURBO,
             cv::Vec3b no_data = cv::Vec3b(0, 0, 0));

  cv::Vec3b operator()(float value) const {
    if (!(value == value) || value == inf_ || value == -inf_) return no_data_;
    return colours_[cv::saturate_cast<uchar>((value - vmin_) * scale_)];
  }
  cv::Vec3b noData() const { return no_data_; }
  double vmin() const { return vmin_; }
  double vmax() const { return vmax_; }

 private:
  std::array<cv::Vec3b, 256> colours_;
  cv::Vec3b no_data_;
  double vmin_, vmax_;
  float scale_;  // 255 / (vmax - vmin)
  static constexpr float inf_ = std::numeric_limits<float>::infinity();
};

/// Colour-maps a float image (CV_32FC1) for people: values outside `valid` (CV_8UC1, may be empty)
/// and non-finite values are drawn dark grey; a labelled scale bar from vmin to vmax is appended on
/// the right. vmin >= vmax picks the 2nd and 98th percentile of the shown values.
cv::Mat colorizeWithScaleBar(const cv::Mat& values, const cv::Mat& valid, double vmin, double vmax,
                             const std::string& label, int colormap = cv::COLORMAP_JET);

}  // namespace multimodal_nvs
