#pragma once
// DepthCompleter: the whole pipeline, points -> angular samples -> model -> validity -> retention.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/models/model_scratch.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

struct DepthMapStats {
  long long pixels = 0;          ///< grid pixels
  long long predicted = 0;       ///< pixels with a finite variance (a prediction)
  long long kept = 0;            ///< valid after variance threshold and retention
  std::size_t points_total = 0;  ///< points handed in
  std::size_t points_non_finite = 0;
  std::size_t points_in_view = 0;  ///< z > 0 and projecting inside the image
  int neighbour_sets = 0;          ///< distinct neighbour sets (tiles in the approximation)
  double shift = 0.0;
  double compute_ms = 0.0;
  /// ground_gp only (empty otherwise): where its ground plane came from (returns, pose,
  /// parameters), which mode ran (dense, sparse), the share of the returns on the RANSAC plane and
  /// the share whose nearest return lies along the image rows (-1 when the mode did not need it).
  std::string ground_source, ground_mode;
  double ground_inlier_fraction = 0.0;
  double ground_scan_line_share = -1.0;
  /// ground_gp's dense mode: returns left out as hidden from the camera (-1: not filtered).
  long long ground_hidden_returns = -1;
  /// ground_gp's dense mode: the depth step (relative) that separated surfaces (-1: another mode).
  double ground_edge_ratio = -1.0;
  /// ground_gp and image_guided: the returns lie on one plane through the sensor (a 2D scanner,
  /// GroundPlaneFit::single_scan_plane): their rows are not measured, so neither model reads the
  /// image's colours at them and image_guided ignores the edges between rows.
  bool ground_single_scan_plane = false;
  /// ground_gp and image_guided: the plane used, as the camera's height above it (m; -1 for the
  /// other models), the optical axis's angle above it and the roll (degrees; GroundPlane).
  double ground_camera_height = -1.0;
  double ground_pitch_deg = 0.0;
  double ground_roll_deg = 0.0;
  /// image_guided only (-1 otherwise): the returns in the camera's view per square degree and the
  /// prior's evidence weight per image pixel that followed from them (ImageGuidedReport).
  double guided_return_density = -1.0;
  double guided_prior_weight = -1.0;
  /// image_guided with ground_gp's prior: the top of the returns' band (degrees of elevation),
  /// above which the prior weighed more (ImageGuidedParams::prior_weight_above_returns); NaN
  /// where it weighed the same everywhere.
  double guided_band_top_deg = std::numeric_limits<double>::quiet_NaN();
};

/// Dense depth on the stride grid, in the reference's layout: depth in metres (camera z), -1 where
/// not kept; variance in m^2, +inf where there is no prediction; valid = kept (0/1).
struct DepthMap {
  StrideGrid grid;
  std::vector<float> depth;
  std::vector<float> variance;
  std::vector<std::uint8_t> valid;
  DepthMapStats stats;
};

/// Runs depth completion. Keeps a thread pool and the per-camera pixel-angle grid between calls, so
/// a node pays for them once; everything else is recomputed per scan. Not thread-safe: one call at
/// a time per instance.
class DepthCompleter {
 public:
  explicit DepthCompleter(int threads = 0);

  /// `points_camera`: the scan in the camera optical frame (non-finite points are dropped and
  /// counted). `image`: the camera image at grid.image's size, which the image_guided model needs
  /// (the others ignore it; it may be empty for them). Throws InputError for invalid parameters,
  /// intrinsics, or a missing image where the model needs one.
  DepthMap complete(const std::vector<Eigen::Vector3d>& points_camera,
                    const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                    const DepthCompletionParams& params, const cv::Mat& image = cv::Mat());
  /// The same, writing into `out` and reusing its buffers: a node calling this per scan with the
  /// same map avoids ~20 MB of fresh, page-faulting allocations per full-resolution frame.
  void complete(const std::vector<Eigen::Vector3d>& points_camera,
                const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                const DepthCompletionParams& params, DepthMap& out,
                const cv::Mat& image = cv::Mat());

  int threads() const { return pool_->size(); }
  /// The pool, idle between calls: for work on a result (the node's coloured cloud) on the same
  /// thread that calls complete(), never during a call.
  ThreadPool& pool() { return *pool_; }

 private:
  const PixelAngleGrid& pixelAngles(const PinholeIntrinsics& intrinsics, const StrideGrid& grid);

  std::unique_ptr<ThreadPool> pool_;
  std::unique_ptr<PixelAngleGrid> angles_;
  std::vector<std::uint8_t> candidate_;  // scratch: valid before retention
  ModelScratch model_scratch_;           // the models' full-image work buffers
};

}  // namespace multimodal_nvs
