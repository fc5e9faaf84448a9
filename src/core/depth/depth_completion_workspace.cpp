#include "multimodal_nvs/core/depth/depth_completion_workspace.hpp"

namespace multimodal_nvs {

std::size_t pointCap(int max_points, const DepthCompletionParams& params) {
  if (max_points < 0) return 0;
  if (max_points > 0) return std::size_t(max_points);
  const bool exact_gp = params.model == DepthModel::kLocalGpMle && params.max_neighbors == 0;
  return exact_gp ? kExactGpPointCap : kLinearModelPointCap;
}

void releaseOversizedBuffers(std::vector<Eigen::Vector3d>& points, DepthMap& depth) {
  if (oversized(points)) std::vector<Eigen::Vector3d>().swap(points);
  if (oversized(depth.depth) || oversized(depth.variance) || oversized(depth.valid)) {
    depth = DepthMap{};
  }
}

const DepthMap& DepthCompletionWorkspace::complete(const PinholeIntrinsics& intrinsics,
                                                   const StrideGrid& grid,
                                                   const DepthCompletionParams& params,
                                                   const cv::Mat& image) {
  try {
    completer_.forThreads(params.threads)
        .complete(points_, intrinsics, grid, params, depth_, image);
  } catch (...) {
    releaseOversizedBuffers(points_, depth_);
    throw;
  }
  releaseOversizedBuffers(points_, depth_);
  return depth_;
}

}  // namespace multimodal_nvs
