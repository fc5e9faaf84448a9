#include "multimodal_nvs/core/eval/nvs_metrics.hpp"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "multimodal_nvs/core/common/json_text.hpp"
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
  std::ostringstream out;
  out << "{\n  \"protocol\": \"REFERENCE.md section 5: GT resized to the render size (bilinear), "
         "uint8 RGB; psnr/ssim on the preview (hole-filled, unlabelled) frames; covered_psnr and "
         "coverage on the raw conditioning frames; means skip non-finite values (null here = +inf: "
         "an exactly reproduced frame)\",\n  \"splat\": \""
      << splat << "\",\n  \"frames\": [\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const NvsFrameMetrics& r = rows[i];
    out << "    {\"frame\": " << r.frame << ", \"gt\": \"" << jsonEscape(r.gt)
        << "\", \"psnr\": " << jsonNumber(r.psnr) << ", \"ssim\": " << jsonNumber(r.ssim)
        << ", \"covered_psnr\": " << jsonNumber(r.covered_psnr)
        << ", \"coverage\": " << jsonNumber(r.coverage) << "}" << (i + 1 < rows.size() ? "," : "")
        << "\n";
  }
  out << "  ],\n";
  for (int skip = 0; skip < 2; ++skip) {
    out << "  \"" << (skip ? "mean_without_reference" : "mean")
        << "\": {\"psnr\": " << jsonNumber(finiteMean(rows, &NvsFrameMetrics::psnr, skip))
        << ", \"ssim\": " << jsonNumber(finiteMean(rows, &NvsFrameMetrics::ssim, skip))
        << ", \"covered_psnr\": "
        << jsonNumber(finiteMean(rows, &NvsFrameMetrics::covered_psnr, skip))
        << ", \"coverage\": " << jsonNumber(finiteMean(rows, &NvsFrameMetrics::coverage, skip))
        << "}" << (skip ? "\n" : ",\n");
  }
  out << "}\n";
  return out.str();
}

}  // namespace multimodal_nvs
