#include "multimodal_nvs/core/eval/nvs_metrics.hpp"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/eval/image_metrics.hpp"

namespace multimodal_nvs {

NvsFrameMetrics nvsFrameMetrics(int frame, const std::string& gt_name,
                                const RenderedFrame& rendered, const cv::Mat& preview,
                                const cv::Mat& gt) {
  NvsFrameMetrics m;
  m.frame = frame;
  m.gt = gt_name;
  m.psnr = psnr(preview, gt);
  m.ssim = ssim(preview, gt);
  m.covered_psnr = coveredPsnr(rendered.bgr, gt, rendered.mask);
  m.coverage = coverage(rendered.mask);
  return m;
}

cv::Mat groundTruthAtRenderSize(const cv::Mat& gt, ImageSize size) {
  cv::Mat out;
  cv::resize(gt, out, cv::Size(size.width, size.height), 0, 0, cv::INTER_LINEAR);
  return out;
}

double finiteMean(const std::vector<NvsFrameMetrics>& rows, double NvsFrameMetrics::*field,
                  bool skip_first) {
  double sum = 0;
  int n = 0;
  for (std::size_t i = skip_first ? 1 : 0; i < rows.size(); ++i) {
    if (std::isfinite(rows[i].*field)) {
      sum += rows[i].*field;
      ++n;
    }
  }
  return n > 0 ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

std::string nvsMetricsJson(const std::vector<NvsFrameMetrics>& rows, const std::string& splat) {
  json::Json frames = json::Json::array();
  for (const NvsFrameMetrics& r : rows) {
    frames.push_back({{"frame", r.frame},
                      {"gt", r.gt},
                      {"psnr", json::number(r.psnr)},
                      {"ssim", json::number(r.ssim)},
                      {"covered_psnr", json::number(r.covered_psnr)},
                      {"coverage", json::number(r.coverage)}});
  }
  json::Json out = {
      {"protocol",
       "REFERENCE.md section 5: GT resized to the render size (bilinear), uint8 RGB; psnr/ssim on "
       "the preview (hole-filled, unlabelled) frames; covered_psnr and coverage on the raw "
       "conditioning frames; means skip non-finite values (null here = +inf: an exactly "
       "reproduced frame)"},
      {"splat", splat},
      {"frames", frames}};
  for (int skip = 0; skip < 2; ++skip) {
    auto mean = [&](double NvsFrameMetrics::*field) {
      return json::number(finiteMean(rows, field, skip != 0));
    };
    out[skip ? "mean_without_reference" : "mean"] = {
        {"psnr", mean(&NvsFrameMetrics::psnr)},
        {"ssim", mean(&NvsFrameMetrics::ssim)},
        {"covered_psnr", mean(&NvsFrameMetrics::covered_psnr)},
        {"coverage", mean(&NvsFrameMetrics::coverage)}};
  }
  return json::document(out);
}

}  // namespace multimodal_nvs
