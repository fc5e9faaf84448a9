#pragma once
// Dilation and erosion of a float image by a full square kernel, on the package's thread pool, in
// O(log k) operations per pixel instead of OpenCV's O(k): the window's extremum is built from
// shifted extrema of doubling width (1, 2, 4, ...; the sparse-table idea), separably by columns and
// by rows. Why hand-written: the `ipbasic` baseline's hole fills dilate by kernels of up to 75 px
// at VoD's spacing, where OpenCV 4.6's row and column filters do 74 comparisons per pixel each and
// run on one thread. Minimum and maximum are exact, so the outputs equal cv::dilate's and
// cv::erode's bit for bit for images without NaN (test_rect_morphology compares them).
#include <opencv2/core.hpp>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

/// cv::dilate(in, out, ksize x ksize rectangle) (default anchor, one iteration, default border)
/// for a CV_32FC1 image without NaN and odd ksize >= 1. `in` may be a ROI: as in OpenCV, pixels
/// outside it are read from its parent. `out` may be `in`.
void rectDilate(const cv::Mat& in, cv::Mat& out, int ksize, ThreadPool& pool);

/// cv::erode with the same kernel and rules.
void rectErode(const cv::Mat& in, cv::Mat& out, int ksize, ThreadPool& pool);

}  // namespace multimodal_nvs
