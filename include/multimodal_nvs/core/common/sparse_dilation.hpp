#pragma once
// Dilation of a sparse non-negative float image by a diamond (L1 ball), computed by writing each
// non-zero pixel's diamond instead of filtering every pixel. Why: the `ipbasic` baseline dilates
// the projected scan (~1 % of the pixels hold a return on VoD's 64-beam LiDAR, far fewer for radar)
// by a diamond of radius 6; filtering costs every pixel radius passes of the 3x3 cross, writing the
// diamonds costs the returns times the diamond's area. Maximum is exact, so the result equals
// cv::dilate with the 3x3 cross iterated `radius` times (test_sparse_dilation compares them).
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

/// out = cv::dilate(in, out, 3x3 cross, default anchor, `radius` iterations) for a CV_32FC1 image
/// whose values are >= 0 and whose positive pixels all appear in `nonzero` (row-major indices into
/// the continuous `in`; duplicates, zero pixels and negative entries are allowed and ignored).
/// `out` must not share memory with `in`. The result does not depend on the thread count.
void dilateSparseByDiamond(const cv::Mat& in, const std::vector<long long>& nonzero, int radius,
                           cv::Mat& out, ThreadPool& pool);

}  // namespace multimodal_nvs
