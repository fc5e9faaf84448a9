#pragma once
// What a node keeps between scans for depth completion: the completer, the scan's points and the
// depth map, with the policies that bound their cost (the point cap, the release of buffers an
// oversized scan left behind).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "multimodal_nvs/core/common/buffer_reuse.hpp"
#include "multimodal_nvs/core/common/thread_count_cached.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"

namespace multimodal_nvs {

/// The automatic cap of the exact reference GP (local_gp_mle without max_neighbors). It solves one
/// GP per distinct neighbour set, and both the sets' number and size grow with the density: on a
/// 320x240 image 10k points take 13 s on one core and 30k points more than 2 minutes and 2.7 GB.
constexpr std::size_t kExactGpPointCap = 5000;
/// The automatic cap of every other model: they are linear in the points (200k: ~4 s for
/// ground_gp).
constexpr std::size_t kLinearModelPointCap = 200000;

/// Most points the model is given per scan for the max_points parameter: < 0 no limit (returns 0),
/// 0 the automatic cap of `params`' model, > 0 that many.
std::size_t pointCap(int max_points, const DepthCompletionParams& params);

/// True when `buffer` holds far more memory than its contents need (capacityFarExceeds).
template <class Buffer>
bool oversized(const Buffer& buffer) {
  return capacityFarExceeds(buffer.capacity(), buffer.size());
}

/// Frees whichever of `points` and `depth` is oversized (the map as a whole), so that memory stays
/// bounded by the usual input, not by the largest one seen (10 million points, an 8000x8000 image).
void releaseOversizedBuffers(std::vector<Eigen::Vector3d>& points, DepthMap& depth);

/// The completer (its thread pool rebuilt only when params.threads changes) and the buffers of one
/// scan, reused between scans: fresh full-resolution buffers cost page faults on every scan (21 MB
/// at 1936x1216). Not thread-safe: one scan at a time.
class DepthCompletionWorkspace {
 public:
  /// The scan in the camera optical frame; the caller fills it before `complete`.
  std::vector<Eigen::Vector3d>& points() { return points_; }

  /// Completes points() into depth(), then releases oversized buffers (also when it throws).
  /// `image`: the camera image (image_guided needs it, the other models ignore it).
  /// Throws InputError for invalid parameters or intrinsics, std::bad_alloc when this host cannot
  /// hold the model's buffers for the scan.
  const DepthMap& complete(const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                           const DepthCompletionParams& params, const cv::Mat& image = cv::Mat());

  const DepthMap& depth() const { return depth_; }
  /// The completer's thread pool for work on depth() between scans (null before the first scan).
  ThreadPool* pool() {
    DepthCompleter* completer = completer_.current();
    return completer != nullptr ? &completer->pool() : nullptr;
  }

 private:
  ThreadCountCached<DepthCompleter> completer_;
  std::vector<Eigen::Vector3d> points_;
  DepthMap depth_;
};

}  // namespace multimodal_nvs
