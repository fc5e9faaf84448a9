#pragma once
// The novel-view metrics of a rendered trajectory against the images recorded at its poses
// (REFERENCE.md section 5), per frame and as the metrics.json that render_conditioning and the
// renderer nodelet's recorded-trajectory export both write.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "multimodal_nvs/core/render/splatting.hpp"

namespace multimodal_nvs {

struct NvsFrameMetrics {
  int frame = 0;   ///< index in the rendered trajectory
  std::string gt;  ///< where the ground truth came from (a path, or a camera stamp)
  double psnr = 0, ssim = 0, covered_psnr = 0, coverage = 0;
};

/// Frame `frame` against `gt` (uint8 BGR, already resized to the render size by bilinear
/// interpolation): PSNR and SSIM on `preview` (the hole-filled frame, before its label is drawn),
/// covered PSNR and coverage on the raw conditioning frame.
NvsFrameMetrics nvsFrameMetrics(int frame, const std::string& gt_name,
                                const RenderedFrame& rendered, const cv::Mat& preview,
                                const cv::Mat& gt);

/// `gt` (any size) resized to `size` as the protocol says: bilinear, no crop.
cv::Mat groundTruthAtRenderSize(const cv::Mat& gt, ImageSize size);

/// Mean of `field` over the finite values only (a frame reproduced exactly, the reference view,
/// has an infinite PSNR over its covered pixels, which no mean can include); `skip_first` leaves
/// the reference view out. NaN when nothing is left.
double finiteMean(const std::vector<NvsFrameMetrics>& rows, double NvsFrameMetrics::*field,
                  bool skip_first);

/// metrics.json: the protocol, the splat mode, one row per frame, and the means with and without
/// the reference view.
std::string nvsMetricsJson(const std::vector<NvsFrameMetrics>& rows, const std::string& splat);

}  // namespace multimodal_nvs
