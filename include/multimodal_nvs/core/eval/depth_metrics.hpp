#pragma once
// Depth accuracy against ground truth: the metrics of the paper's depth table over the
// ground-truth pixels of a stride grid, and the ground truth itself — a LiDAR scan projected into
// the image (nearest return per pixel) or an exact dense depth image sampled on the grid.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"

namespace multimodal_nvs {

/// Running sums behind the depth metrics, so frames, shards and machines can be merged exactly.
struct DepthErrorSums {
  long long gt_pixels = 0;    ///< ground-truth pixels considered (with or without a prediction)
  long long count = 0;        ///< of those, the ones with a prediction: the evaluated pixels
  double abs_error = 0.0;     ///< sum |p - g|
  double sq_error = 0.0;      ///< sum (p - g)^2
  double sq_log_error = 0.0;  ///< sum (ln p - ln g)^2
  double abs_rel = 0.0;       ///< sum |p - g| / g
  long long delta1 = 0;       ///< number with max(p/g, g/p) < 1.25

  void add(double prediction, double truth);
  void merge(const DepthErrorSums& other);
};

/// MAE and RMSE in metres, RMSE_log (natural log), AbsRel and delta<1.25 (fraction) over the
/// evaluated pixels, and coverage = evaluated / ground-truth pixels. NaN where count is 0.
struct DepthMetrics {
  long long gt_pixels = 0;
  long long count = 0;
  double mae, rmse, rmse_log, abs_rel, delta1, coverage;

  static DepthMetrics from(const DepthErrorSums& sums);
};

struct DepthEvaluationOptions {
  /// Ground truth deeper than this is ignored (range cap); <= 0: no cap. Predictions are clipped to
  /// the cap as well (the usual protocol of Eigen et al. / Monodepth).
  double max_depth = 0.0;
  /// Predictions are clipped to at least this before the log and the ratios.
  double min_prediction = 1e-3;
};

/// Sums over the pixels with ground truth (finite, > 0, within the cap). With a `mask`, a pixel
/// counts as predicted when mask != 0 and the prediction is finite (a depth <= 0 is then an error,
/// clipped to min_prediction); without one, when the prediction is finite and > 0 (the DepthMap
/// convention: -1 = not kept). All arrays hold `n` values of the same grid.
DepthErrorSums evaluateDepth(const float* prediction, const std::uint8_t* mask, const float* truth,
                             std::size_t n, const DepthEvaluationOptions& options);

/// prediction - truth at every ground-truth pixel evaluateDepth considers (same mask, clipping and
/// cap), in grid order, NaN where that pixel has no prediction. Models evaluated on the same grid
/// against the same truth give arrays of the same length, entry for entry: what comparing them on
/// only the pixels that all of them predict needs (a model that predicts only near its samples,
/// such as linear interpolation inside the samples' hull, is otherwise scored on easier pixels).
std::vector<float> signedErrorsAtTruth(const float* prediction, const std::uint8_t* mask,
                                       const float* truth, std::size_t n,
                                       const DepthEvaluationOptions& options);

/// Calibration of a predictive variance: for each nominal level p, the number of
/// evaluated ground-truth pixels g inside the central Gaussian interval mean +- z_p sigma, where
/// P(|N(0, 1)| <= z_p) = p. A calibrated model has observed(i) close to levels[i] at every level.
struct CalibrationCounts {
  std::vector<double> levels;     ///< nominal coverage, each in (0, 1)
  std::vector<long long> inside;  ///< per level: evaluated pixels inside the interval
  long long count = 0;            ///< evaluated pixels

  /// Share inside the interval of level i (NaN without evaluated pixels).
  double observed(std::size_t i) const;
  /// Adds another frame's counts; throws InputError when the levels differ.
  void merge(const CalibrationCounts& other);
};

/// z with P(|N(0, 1)| <= z) = p, for p in (0, 1) (1.959964 for 0.95).
double centralNormalQuantile(double p);

/// Interval coverage over the same pixels as evaluateDepth (same mask, clipping and cap), with the
/// per-pixel `variance` (m^2) of the prediction. A pixel with a non-finite or negative variance
/// counts as outside every interval. Throws InputError for a level outside (0, 1).
CalibrationCounts evaluateCalibration(const float* prediction, const float* variance,
                                      const std::uint8_t* mask, const float* truth, std::size_t n,
                                      const DepthEvaluationOptions& options,
                                      const std::vector<double>& levels);

/// Ground truth from a range scan in the camera frame: camera z of the nearest return per grid
/// pixel (pixel = round(u / stride), round(v / stride) of its projection), 0 where no return lands.
/// Points with z <= 0 or non-finite coordinates are ignored.
std::vector<float> projectDepthGroundTruth(const std::vector<Eigen::Vector3d>& points_camera,
                                           const PinholeIntrinsics& intrinsics,
                                           const StrideGrid& grid);

/// A dense full-resolution depth image (row-major `height` x `width`, <= 0 or non-finite = none)
/// sampled at the grid pixels (r * stride, c * stride). Throws InputError when the image size is
/// not the grid's image size.
std::vector<float> sampleDenseGroundTruth(const std::vector<float>& depth, int height, int width,
                                          const StrideGrid& grid);

}  // namespace multimodal_nvs
