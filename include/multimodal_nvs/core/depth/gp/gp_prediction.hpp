#pragma once
// The GP's per-pixel step, the package's hottest loop (compiled with FMA: no parity needed here).
#include "multimodal_nvs/core/depth/gp/local_gp.hpp"

namespace multimodal_nvs {

/// The arithmetic of the per-pixel step. Double: the exact models (the reference computes in
/// float64). Single: twice the SIMD lanes, for models with no parity to keep (ground_gp's
/// residual GP); the Cholesky factor and the weights are still computed in double.
enum class PredictionPrecision { kDouble, kSingle };

/// Posterior mean and variance at one pixel from a factorised set (the per-pixel step):
/// k* = a^2 exp(-d^2 / 2l^2), w = L^-1 k*, mean = shift + w.beta, var = a^2 + sigma^2 - |w|^2 (>=
/// 0).
void predictFromFactor(const double* packed_factor, const double* beta, const float* azimuth,
                       const float* elevation, int n, double length_scale,
                       const LocalGpParams& params, const float* pixel_az, const float* pixel_el,
                       int pixels, double shift, float* mean_out, float* var_out,
                       PredictionPrecision precision = PredictionPrecision::kDouble);

/// Pixels [0, count) of one run: their angles in, their mean and variance out.
struct PixelRun {
  const float* az;
  const float* el;
  float* mean;
  float* variance;
  int count;
};

/// The same step for the pixels of several runs (one set's segments in several rows): the
/// SIMD blocks span the runs, so short segments share their set-up.
void predictFromFactor(const double* packed_factor, const double* beta, const float* azimuth,
                       const float* elevation, int n, double length_scale,
                       const LocalGpParams& params, const PixelRun* runs, int run_count,
                       double shift, PredictionPrecision precision = PredictionPrecision::kDouble);

}  // namespace multimodal_nvs
