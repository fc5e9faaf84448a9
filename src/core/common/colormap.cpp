#include "multimodal_nvs/core/common/colormap.hpp"

#include "multimodal_nvs/core/common/errors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace multimodal_nvs {

ColorScale::ColorScale(double vmin, double vmax, int colormap, cv::Vec3b no_data)
    : no_data_(no_data), vmin_(vmin), vmax_(vmax) {
  if (!(vmin < vmax) || !std::isfinite(vmin) || !std::isfinite(vmax)) {
    throw InputError("colour scale: need finite vmin < vmax, got " + std::to_string(vmin) + " .. " +
                     std::to_string(vmax));
  }
  scale_ = static_cast<float>(255.0 / (vmax - vmin));
  cv::Mat ramp(256, 1, CV_8UC1), coloured;
  for (int i = 0; i < 256; ++i)
    ramp.at<uchar>(i) = static_cast<uchar>(i);
  cv::applyColorMap(ramp, coloured, colormap);
  for (int i = 0; i < 256; ++i)
    colours_[i] = coloured.at<cv::Vec3b>(i);
}

cv::Mat colorizeWithScaleBar(const cv::Mat& values, const cv::Mat& valid, double vmin, double vmax,
                             const std::string& label, int colormap) {
  CV_Assert(values.type() == CV_32FC1);
  cv::Mat shown(values.size(), CV_8UC1, cv::Scalar(0));
  for (int r = 0; r < values.rows; ++r) {
    for (int c = 0; c < values.cols; ++c) {
      const float v = values.at<float>(r, c);
      shown.at<uint8_t>(r, c) = std::isfinite(v) && (valid.empty() || valid.at<uint8_t>(r, c));
    }
  }
  if (!(vmin < vmax)) {
    std::vector<float> samples;
    for (int r = 0; r < values.rows; ++r) {
      for (int c = 0; c < values.cols; ++c) {
        if (shown.at<uint8_t>(r, c)) samples.push_back(values.at<float>(r, c));
      }
    }
    if (samples.empty()) {
      vmin = 0.0;
      vmax = 1.0;
    } else {
      auto at = [&](double q) {
        auto it = samples.begin() + static_cast<long>(q * (samples.size() - 1));
        std::nth_element(samples.begin(), it, samples.end());
        return static_cast<double>(*it);
      };
      vmin = at(0.02);
      vmax = at(0.98);
      if (!(vmax > vmin)) vmax = vmin + 1.0;
    }
  }
  const ColorScale scale(vmin, vmax, colormap, cv::Vec3b(40, 40, 40));
  cv::Mat colored(values.size(), CV_8UC3);
  for (int r = 0; r < values.rows; ++r) {
    for (int c = 0; c < values.cols; ++c) {
      colored.at<cv::Vec3b>(r, c) =
          shown.at<uint8_t>(r, c) ? scale(values.at<float>(r, c)) : scale.noData();
    }
  }

  // Scale bar: a vertical gradient with tick labels, height of the image, on a white margin.
  const int bar_width = std::max(20, values.cols / 40);
  const double font = std::max(0.35, values.rows / 900.0);
  // Room for the label above the bar and the top tick's text below it, and for the label's width.
  int baseline = 0;
  const cv::Size label_size = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, font, 1, &baseline);
  const int margin = std::max(bar_width * 4 + 40, label_size.width + 20);
  cv::Mat canvas(values.rows, values.cols + margin, CV_8UC3, cv::Scalar(255, 255, 255));
  colored.copyTo(canvas(cv::Rect(0, 0, values.cols, values.rows)));
  const int wanted_top = std::max({20, values.rows / 20, 2 * label_size.height + baseline + 12});
  const int top = std::min(wanted_top, std::max(1, (values.rows - 2) / 2));  // tiny images too
  const int bottom = values.rows - top;
  cv::Mat gradient(bottom - top, 1, CV_8UC1);
  for (int i = 0; i < gradient.rows; ++i) {
    gradient.at<uint8_t>(i) = static_cast<uint8_t>(255 - 255 * i / std::max(1, gradient.rows - 1));
  }
  cv::Mat gradient_colored;
  cv::applyColorMap(gradient, gradient_colored, colormap);
  cv::resize(gradient_colored, gradient_colored, cv::Size(bar_width, gradient.rows), 0, 0,
             cv::INTER_NEAREST);
  const int x0 = values.cols + 10;
  gradient_colored.copyTo(canvas(cv::Rect(x0, top, bar_width, gradient.rows)));
  for (int t = 0; t <= 4; ++t) {
    const double v = vmax - (vmax - vmin) * t / 4.0;
    const int y = top + (bottom - top - 1) * t / 4;
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    cv::line(canvas, {x0 + bar_width, y}, {x0 + bar_width + 5, y}, cv::Scalar(0, 0, 0), 1);
    cv::putText(canvas, text, {x0 + bar_width + 8, y + 5}, cv::FONT_HERSHEY_SIMPLEX, font,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  cv::putText(canvas, label, {x0, label_size.height + 4}, cv::FONT_HERSHEY_SIMPLEX, font,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return canvas;
}

}  // namespace multimodal_nvs
