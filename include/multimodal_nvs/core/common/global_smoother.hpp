#pragma once
// The weighted-least-squares smoother of Min et al., "Fast Global Image Smoothing Based on
// Weighted Least Squares" (IEEE TIP 2014), as OpenCV's ximgproc::FastGlobalSmootherFilter
// defines it — the same edge weights, lambda schedule and pass order — but for several planes at
// once: the elimination coefficients of each 1D solve depend only on the guide and lambda, so they
// are computed once per pass and shared by every plane (OpenCV recomputes them per channel and
// allocates per call: 85 ms on a 968x608 three-channel image on 2 cores; see global_smoother.cpp).
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

struct GlobalSmootherParams {
  double lambda = 4000.0;     ///< smoothness weight of the first iteration
  double sigma_color = 8.0;   ///< guide difference (8-bit, Euclidean over BGR) of weight 1/e
  double attenuation = 0.25;  ///< lambda is multiplied by this after each iteration
  int iterations = 3;         ///< each: one horizontal and one vertical 1D solve
  /// false: the vertical solves ignore the guide (every weight that of equal colours), the
  /// horizontal ones still follow it. For evidence whose row is not known (a 2D scanner's returns
  /// project to the row of its own scan plane, not of the surface that returned them) an edge
  /// between rows says nothing about where the evidence belongs; an edge between columns still
  /// does (its azimuth is measured).
  bool vertical_edges = true;
};

/// Smooths `planes` (CV_32FC1 each, the guide's size) in place, guided by `guide` (CV_8UC3).
/// Each iteration solves, along every row and then every column, (I + lambda_k L) u = f with the
/// 1D Laplacian L of weights exp(-|g_p - g_q| / sigma_color) between neighbours (Min et al.):
/// linear in the planes, so sums of weighted evidence can be smoothed and divided afterwards.
void smoothAlongGuide(const cv::Mat& guide, std::vector<cv::Mat>& planes,
                      const GlobalSmootherParams& params, ThreadPool& pool);

}  // namespace multimodal_nvs
