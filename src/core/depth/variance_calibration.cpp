#include "multimodal_nvs/core/depth/variance_calibration.hpp"

#include <algorithm>
#include <cmath>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/eval/depth_metrics.hpp"

namespace multimodal_nvs {

void VarianceCalibration::applyTo(std::vector<float>& variance, ThreadPool& pool) const {
  constexpr long long kChunk = 1 << 16;
  const long long n = static_cast<long long>(variance.size());
  const float s = static_cast<float>(scale);
  float* const v = variance.data();
  pool.parallelFor((n + kChunk - 1) / kChunk, [&](long long c, int) {
    const long long end = std::min(n, (c + 1) * kChunk);
    for (long long i = c * kChunk; i < end; ++i)
      v[i] *= s;
  });
}

void VarianceScaleFit::add(const float* mean, const float* variance, const float* truth,
                           const unsigned char* mask, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    if (mask && !mask[i]) continue;
    const double p = mean[i], v = variance[i], g = truth[i];
    if (!std::isfinite(p) || !std::isfinite(v) || !(v > 0.0) || !std::isfinite(g) || !(g > 0.0)) {
      continue;
    }
    ratios_.push_back((p - g) * (p - g) / v);
  }
}

VarianceCalibration VarianceScaleFit::fit(double level, double target) const {
  if (ratios_.empty()) throw InputError("variance calibration: no pixel with truth and prediction");
  if (!(target > 0.0 && target < 1.0)) throw InputError("variance calibration: target in (0, 1)");
  const double z = centralNormalQuantile(level);  // throws for a level outside (0, 1)
  std::vector<double> r = ratios_;
  const std::size_t k = std::min(r.size() - 1, static_cast<std::size_t>(target * r.size()));
  std::nth_element(r.begin(), r.begin() + k, r.end());
  VarianceCalibration c;
  // A perfect fit (every error 0) keeps the raw variance rather than collapsing it.
  c.scale = r[k] > 0.0 ? r[k] / (z * z) : 1.0;
  return c;
}

}  // namespace multimodal_nvs
