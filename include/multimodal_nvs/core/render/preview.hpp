#pragma once
// A classical hole fill for previewing conditioning frames (GEN3C fills them for real).
#include <opencv2/core.hpp>
#include <string>

namespace multimodal_nvs {

/// Fills the holes of a conditioning frame by push-pull (Gortler et al. 1996): covered pixels are
/// averaged down an image pyramid, then every hole takes the colour interpolated up from the
/// first coarser level that has data. Covered pixels keep their colour exactly. A classical fill
/// so a person can look at a whole frame without the diffusion model; it is not a prediction.
/// `bgr` CV_8UC3, `mask` CV_8UC1 (nonzero = covered), same size. An all-hole frame stays black.
cv::Mat fillHolesPushPull(const cv::Mat& bgr, const cv::Mat& mask);

/// Writes `label` in the top-left corner (white on a dark box) so a filled frame cannot be mistaken
/// for a generated one.
void drawPreviewLabel(cv::Mat& bgr, const std::string& label = "PREVIEW: classical hole fill");

}  // namespace multimodal_nvs
