#include "multimodal_nvs/core/eval/depth_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

void DepthErrorSums::add(double p, double g) {
  const double diff = p - g;
  const double log_diff = std::log(p) - std::log(g);
  ++count;
  abs_error += std::abs(diff);
  sq_error += diff * diff;
  sq_log_error += log_diff * log_diff;
  abs_rel += std::abs(diff) / g;
  delta1 += std::max(p / g, g / p) < 1.25;
}

void DepthErrorSums::merge(const DepthErrorSums& o) {
  gt_pixels += o.gt_pixels;
  count += o.count;
  abs_error += o.abs_error;
  sq_error += o.sq_error;
  sq_log_error += o.sq_log_error;
  abs_rel += o.abs_rel;
  delta1 += o.delta1;
}

DepthMetrics DepthMetrics::from(const DepthErrorSums& s) {
  DepthMetrics m;
  m.gt_pixels = s.gt_pixels;
  m.count = s.count;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double n = static_cast<double>(s.count);
  m.mae = s.count > 0 ? s.abs_error / n : nan;
  m.rmse = s.count > 0 ? std::sqrt(s.sq_error / n) : nan;
  m.rmse_log = s.count > 0 ? std::sqrt(s.sq_log_error / n) : nan;
  m.abs_rel = s.count > 0 ? s.abs_rel / n : nan;
  m.delta1 = s.count > 0 ? s.delta1 / n : nan;
  m.coverage = s.gt_pixels > 0 ? n / static_cast<double>(s.gt_pixels) : nan;
  return m;
}

namespace {

/// What pixel i contributes to the metrics; evaluateDepth and evaluateCalibration both select
/// and clip through here, so they always describe the same pixels.
enum class PixelRole { kNoTruth, kTruthOnly, kEvaluated };
PixelRole evaluatedPixel(const float* prediction, const std::uint8_t* mask, const float* truth,
                         std::size_t i, const DepthEvaluationOptions& options, double& clipped) {
  const float g = truth[i];
  if (!(std::isfinite(g) && g > 0.0f)) return PixelRole::kNoTruth;
  const bool capped = options.max_depth > 0.0;
  if (capped && g > options.max_depth) return PixelRole::kNoTruth;
  const float p = prediction[i];
  const bool predicted =
      mask != nullptr ? mask[i] != 0 && std::isfinite(p) : std::isfinite(p) && p > 0.0f;
  if (!predicted) return PixelRole::kTruthOnly;
  clipped = std::max<double>(p, options.min_prediction);
  if (capped) clipped = std::min(clipped, options.max_depth);
  return PixelRole::kEvaluated;
}

}  // namespace

DepthErrorSums evaluateDepth(const float* prediction, const std::uint8_t* mask, const float* truth,
                             std::size_t n, const DepthEvaluationOptions& options) {
  DepthErrorSums sums;
  for (std::size_t i = 0; i < n; ++i) {
    double clipped = 0.0;
    const PixelRole role = evaluatedPixel(prediction, mask, truth, i, options, clipped);
    if (role == PixelRole::kNoTruth) continue;
    ++sums.gt_pixels;
    if (role == PixelRole::kEvaluated) sums.add(clipped, truth[i]);
  }
  return sums;
}

std::vector<float> signedErrorsAtTruth(const float* prediction, const std::uint8_t* mask,
                                       const float* truth, std::size_t n,
                                       const DepthEvaluationOptions& options) {
  std::vector<float> errors;
  for (std::size_t i = 0; i < n; ++i) {
    double clipped = 0.0;
    const PixelRole role = evaluatedPixel(prediction, mask, truth, i, options, clipped);
    if (role == PixelRole::kNoTruth) continue;
    errors.push_back(role == PixelRole::kEvaluated ? static_cast<float>(clipped - double(truth[i]))
                                                   : std::numeric_limits<float>::quiet_NaN());
  }
  return errors;
}

double CalibrationCounts::observed(std::size_t i) const {
  return count > 0 ? static_cast<double>(inside.at(i)) / static_cast<double>(count)
                   : std::numeric_limits<double>::quiet_NaN();
}

void CalibrationCounts::merge(const CalibrationCounts& other) {
  if (other.levels != levels) throw InputError("calibration counts of different levels");
  count += other.count;
  for (std::size_t i = 0; i < inside.size(); ++i)
    inside[i] += other.inside[i];
}

double centralNormalQuantile(double p) {
  if (!(p > 0.0 && p < 1.0)) throw InputError("calibration level must be in (0, 1)");
  // P(|Z| <= z) = erf(z / sqrt 2) is increasing: bisection to double precision (no closed form).
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erf(mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

CalibrationCounts evaluateCalibration(const float* prediction, const float* variance,
                                      const std::uint8_t* mask, const float* truth, std::size_t n,
                                      const DepthEvaluationOptions& options,
                                      const std::vector<double>& levels) {
  CalibrationCounts counts;
  counts.levels = levels;
  counts.inside.assign(levels.size(), 0);
  std::vector<double> z(levels.size());
  for (std::size_t l = 0; l < levels.size(); ++l)
    z[l] = centralNormalQuantile(levels[l]);
  for (std::size_t i = 0; i < n; ++i) {
    double clipped = 0.0;
    if (evaluatedPixel(prediction, mask, truth, i, options, clipped) != PixelRole::kEvaluated) {
      continue;
    }
    const float g = truth[i];
    ++counts.count;
    const double v = variance[i];
    if (!(std::isfinite(v) && v >= 0.0)) continue;
    const double error = std::abs(clipped - g), sigma = std::sqrt(v);
    for (std::size_t l = 0; l < levels.size(); ++l)
      counts.inside[l] += error <= z[l] * sigma;
  }
  return counts;
}

std::vector<float> projectDepthGroundTruth(const std::vector<Eigen::Vector3d>& points,
                                           const PinholeIntrinsics& k, const StrideGrid& grid) {
  const int rows = grid.rows(), cols = grid.cols();
  std::vector<float> gt(static_cast<std::size_t>(grid.size()), 0.0f);
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite() || !(p.z() > 0.0)) continue;
    double u = 0, v = 0;
    if (!k.project(p.x(), p.y(), p.z(), &u, &v)) continue;  // through the lens model, if any
    const double c = std::round(u / grid.stride), r = std::round(v / grid.stride);
    if (!(c >= 0 && r >= 0 && c < cols && r < rows)) continue;
    float& pixel = gt[static_cast<std::size_t>(r) * cols + static_cast<std::size_t>(c)];
    const float z = static_cast<float>(p.z());
    if (pixel == 0.0f || z < pixel) pixel = z;
  }
  return gt;
}

std::vector<float> sampleDenseGroundTruth(const std::vector<float>& depth, int height, int width,
                                          const StrideGrid& grid) {
  if (height != grid.image.height || width != grid.image.width ||
      depth.size() != static_cast<std::size_t>(height) * width) {
    throw InputError("dense ground truth is " + std::to_string(height) + "x" +
                     std::to_string(width) + " but the image is " +
                     std::to_string(grid.image.height) + "x" + std::to_string(grid.image.width));
  }
  const int rows = grid.rows(), cols = grid.cols();
  std::vector<float> gt(static_cast<std::size_t>(grid.size()), 0.0f);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const float z = depth[static_cast<std::size_t>(r) * grid.stride * width +
                            static_cast<std::size_t>(c) * grid.stride];
      gt[static_cast<std::size_t>(r) * cols + c] = std::isfinite(z) && z > 0.0f ? z : 0.0f;
    }
  }
  return gt;
}

}  // namespace multimodal_nvs
