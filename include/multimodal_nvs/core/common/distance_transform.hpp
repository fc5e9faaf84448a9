#pragma once
// Exact Euclidean distance transform of a binary image (pixel units), on the thread pool.
#include <opencv2/core.hpp>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

/// Distance of every pixel of `mask` (CV_8UC1) to the nearest zero pixel, as
/// cv::distanceTransform(mask, distance, DIST_L2, DIST_MASK_PRECISE, CV_32F) defines it: the float
/// square root of the exact integer squared distance. Separable algorithm of Meijster, Roerdink and
/// Hesselink ("A general algorithm for computing distance transforms in linear time", 2000) in
/// integer arithmetic: column sweeps, then the lower envelope of parabolas per row. Rows and column
/// bands run on `pool`; every output depends only on the input, never on the thread count.
/// `vertical` is scratch (CV_32SC1, the per-column distances) kept by the caller across calls.
/// Without any zero pixel every distance is at least rows + cols (a seed beyond the image).
void exactDistanceTransform(const cv::Mat& mask, cv::Mat& distance, cv::Mat& vertical,
                            ThreadPool& pool);

}  // namespace multimodal_nvs
