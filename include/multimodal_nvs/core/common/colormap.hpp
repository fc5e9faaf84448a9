#pragma once
// Colour maps with a labelled scale bar, for showing depth and variance to people.
#include <opencv2/core.hpp>
#include <string>

namespace multimodal_nvs {

/// Colour-maps a float image (CV_32FC1) for people: values outside `valid` (CV_8UC1, may be empty)
/// and non-finite values are drawn dark grey; a labelled scale bar from vmin to vmax is appended on
/// the right. vmin >= vmax picks the 2nd and 98th percentile of the shown values.
cv::Mat colorizeWithScaleBar(const cv::Mat& values, const cv::Mat& valid, double vmin, double vmax,
                             const std::string& label, int colormap = 2 /* cv::COLORMAP_JET */);

}  // namespace multimodal_nvs
