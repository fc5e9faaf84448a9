#include "multimodal_nvs/core/render/preview.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

cv::Mat fillHolesPushPull(const cv::Mat& bgr, const cv::Mat& mask) {
  if (bgr.type() != CV_8UC3 || mask.type() != CV_8UC1 || bgr.size() != mask.size()) {
    throw InputError("preview fill needs an 8-bit BGR frame and an 8-bit mask of the same size");
  }
  // Level 0: colour premultiplied by a {0, 1} weight.
  std::vector<cv::Mat> colour{cv::Mat()}, weight{cv::Mat()};
  cv::Mat w0;
  mask.convertTo(w0, CV_32F);
  cv::threshold(w0, w0, 0.0, 1.0, cv::THRESH_BINARY);
  bgr.convertTo(colour[0], CV_32FC3);
  cv::Mat w0c;
  cv::merge(std::vector<cv::Mat>{w0, w0, w0}, w0c);
  colour[0] = colour[0].mul(w0c);
  weight[0] = w0;
  // Push: halve until one pixel; INTER_AREA averages premultiplied colour and weight alike.
  while (colour.back().rows > 1 || colour.back().cols > 1) {
    const cv::Size half((colour.back().cols + 1) / 2, (colour.back().rows + 1) / 2);
    cv::Mat c, w;
    cv::resize(colour.back(), c, half, 0, 0, cv::INTER_AREA);
    cv::resize(weight.back(), w, half, 0, 0, cv::INTER_AREA);
    colour.push_back(c);
    weight.push_back(w);
  }
  // Pull: normalise each level where it has data and blend in the upsampled coarser level where
  // the weight is below 1 (partial or empty), from the top down.
  cv::Mat filled;  // normalised colour of the coarser level
  for (int level = static_cast<int>(colour.size()) - 1; level >= 0; --level) {
    const cv::Mat& c = colour[static_cast<std::size_t>(level)];
    const cv::Mat& w = weight[static_cast<std::size_t>(level)];
    cv::Mat up;
    if (!filled.empty()) cv::resize(filled, up, c.size(), 0, 0, cv::INTER_LINEAR);
    cv::Mat current(c.size(), CV_32FC3);
    for (int r = 0; r < c.rows; ++r) {
      const cv::Vec3f* cr = c.ptr<cv::Vec3f>(r);
      const float* wr = w.ptr<float>(r);
      const cv::Vec3f* ur = up.empty() ? nullptr : up.ptr<cv::Vec3f>(r);
      cv::Vec3f* out = current.ptr<cv::Vec3f>(r);
      for (int col = 0; col < c.cols; ++col) {
        const float a = std::min(1.0f, wr[col]);
        const cv::Vec3f mean = wr[col] > 0.0f ? cr[col] / wr[col] : cv::Vec3f(0, 0, 0);
        out[col] = ur == nullptr ? mean : a * mean + (1.0f - a) * ur[col];
      }
    }
    filled = current;
  }
  cv::Mat result;
  filled.convertTo(result, CV_8UC3);
  bgr.copyTo(result, mask);  // covered pixels exactly as rendered
  return result;
}

void drawPreviewLabel(cv::Mat& bgr, const std::string& label) {
  const double scale = std::max(0.4, bgr.rows / 900.0);
  const int thickness = std::max(1, static_cast<int>(scale * 1.5));
  int baseline = 0;
  const cv::Size text =
      cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
  const int pad = static_cast<int>(6 * scale);
  cv::rectangle(bgr, cv::Rect(0, 0, text.width + 2 * pad, text.height + baseline + 2 * pad),
                cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(bgr, label, cv::Point(pad, pad + text.height), cv::FONT_HERSHEY_SIMPLEX, scale,
              cv::Scalar(255, 255, 255), thickness, cv::LINE_AA);
}

}  // namespace multimodal_nvs
