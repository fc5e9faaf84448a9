#pragma once
// Calibrating a model's predictive variance against ground truth: one scale per model (and input
// mode), fitted on development frames so that the central interval mean +- z sigma holds the
// nominal share of the truth, then applied to every prediction. A constant scale keeps the order of
// the variances, so retention keeps the same pixels; what changes is what the variance promises.
#include <cstddef>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

/// calibrated variance = scale * raw variance.
struct VarianceCalibration {
  double scale = 1.0;

  float apply(float variance) const { return static_cast<float>(scale * variance); }
  /// Every element, in parallel (+inf stays +inf: no prediction).
  void applyTo(std::vector<float>& variance, ThreadPool& pool) const;
};

/// Collects, over any number of frames, the squared standardised errors (p - g)^2 / variance of
/// the pixels with a prediction (finite mean, finite variance > 0) and ground truth (finite > 0),
/// and gives the variance scale under which the central interval of nominal coverage `level`
/// (z = centralNormalQuantile(level), 1.96 for 0.95) holds exactly `target` of them: the target
/// quantile of those errors divided by z^2. Fit on development frames only.
class VarianceScaleFit {
 public:
  /// `mask` (optional): only pixels with mask != 0 count (e.g. the kept ones).
  void add(const float* mean, const float* variance, const float* truth, const unsigned char* mask,
           std::size_t n);
  std::size_t count() const { return ratios_.size(); }
  /// Throws InputError without pixels or for level/target outside (0, 1).
  VarianceCalibration fit(double level = 0.95, double target = 0.95) const;

 private:
  std::vector<double> ratios_;
};

}  // namespace multimodal_nvs
