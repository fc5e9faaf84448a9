#pragma once
// Renders a coloured cloud into target views: z-buffered points or GEN3C's splatting.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"

namespace multimodal_nvs {

enum class SplatMode {
  /// GEN3C's own forward warp: bilinear 4-pixel splat, soft z-buffer weight, weighted mean.
  kGen3c,
  /// Nearest surface wins; the footprint grows with magnification so approached surfaces stay
  /// closed.
  kZbuffer,
};

SplatMode parseSplatMode(const std::string& name);  ///< "gen3c" | "zbuffer"; throws InputError
std::string toString(SplatMode mode);

struct SplatParams {
  SplatMode mode = SplatMode::kGen3c;
  /// gen3c: frames rendered together share the maximum log-depth of the soft z-buffer weight
  /// (GEN3C renders in batches of 2: frames 0-1, 2-3, ...).
  int gen3c_batch = 2;
  /// gen3c: w = 1 / (exp(sharpness * log1p(z) / max log1p(z)) + 1e-7).
  float gen3c_sharpness = 50.0f;
  /// zbuffer: square footprint of ceil(magnification) pixels (capped), where magnification is how
  /// many target pixels one source pixel spans at the point's depth. Off: one pixel per point.
  bool grow_footprint = true;
  int max_footprint = 15;
};

/// One conditioning frame. Channel order is OpenCV's (BGR).
struct RenderedFrame {
  cv::Mat bgr;    ///< CV_8UC3, 0 in holes
  cv::Mat mask;   ///< CV_8UC1, 255 where covered, 0 in holes
  cv::Mat depth;  ///< CV_32FC1, z in the target camera, 0 in holes
  /// gen3c mode only (empty otherwise): the weighted mean in [-1, 1] before quantisation, holes -1.
  cv::Mat signed_bgr;  ///< CV_32FC3
};

/// Renders a coloured cloud into the views of a trajectory. Keeps per-thread scratch buffers so
/// that rendering many frames allocates nothing per point or per frame after the first call.
/// Frames are distributed over the pool; results do not depend on the thread count.
class PointSplatter {
 public:
  explicit PointSplatter(int threads = 0);

  int threads() const { return pool_.size(); }

  /// Renders frames [first, first + count) of `trajectory` into `frames` (resized to `count`;
  /// buffers already of the right size are reused). Throws InputError for an empty cloud, a frame
  /// range outside the trajectory, or invalid parameters.
  void render(const ColoredCloud& cloud, const Trajectory& trajectory, int first, int count,
              const SplatParams& params, std::vector<RenderedFrame>& frames);

  std::vector<RenderedFrame> render(const ColoredCloud& cloud, const Trajectory& trajectory,
                                    int first, int count, const SplatParams& params);

 private:
  void renderZbuffer(const ColoredCloud& cloud, const TargetCamera& camera, ImageSize size,
                     const SplatParams& params, int worker, RenderedFrame& out);
  void renderGen3c(const ColoredCloud& cloud, const TargetCamera& camera, ImageSize size,
                   const SplatParams& params, float max_log_depth, int worker, RenderedFrame& out);

  ThreadPool pool_;
  std::vector<std::vector<std::uint64_t>> depth_keys_;  ///< zbuffer scratch, one per worker
  std::vector<std::vector<float>> accumulators_;        ///< gen3c scratch, one per worker
};

/// Largest target-camera z of the cloud in `camera` (the soft z-buffer normaliser); -inf if empty.
float maxTargetDepth(const ColoredCloud& cloud, const TargetCamera& camera);

}  // namespace multimodal_nvs
