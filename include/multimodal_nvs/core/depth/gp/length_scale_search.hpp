#pragma once
// The reference's marginal-likelihood length-scale search, one neighbour set per SIMD lane.
#include <vector>

#include "multimodal_nvs/core/common/simd_buffer.hpp"
#include "multimodal_nvs/core/depth/gp/local_gp.hpp"

namespace multimodal_nvs {

/// The marginal-likelihood length-scale search (golden section, reference sequence) for up to
/// kLanes neighbour sets of the same size at once, one set per SIMD lane.
///
/// Every lane runs exactly the operations a lone set would (same kernel exponentials, same
/// Cholesky order, one log per 16 pivots), so a set's result does not depend on which sets share
/// its batch: batching only fills the 8 double lanes of an AVX-512 register with useful work.
/// Used for sets of 3..kMaxBatchedSize samples; two-sample sets need the reference-exact path and
/// one-sample sets need no likelihood at all (see depth_models.cpp).
class LengthScaleSearch {
 public:
  static constexpr int kLanes = 8;
  static constexpr int kMaxBatchedSize = 32;

  explicit LengthScaleSearch(const LocalGpParams& params) : params_(params) {}

  /// `lanes` sets (1..kLanes) of `n` samples each; set s has angles az[s][i], el[s][i] and shifted
  /// targets y[s][i]. Writes one length scale per set.
  void search(int n, int lanes, const float* const* az, const float* const* el,
              const double* const* y, double* length_scale);

  /// Negative log marginal likelihood of every lane at its own length scale (+inf on a failed
  /// Cholesky). Exposed for tests.
  void negLogMarginalLikelihood(const double* length_scale, double* out);
  /// Loads the data as search() does, without searching.
  void load(int n, int lanes, const float* const* az, const float* const* el,
            const double* const* y);

 private:
  LocalGpParams params_;
  int n_ = 0;
  std::vector<double> sq_dist_;  // [packed (i, j), lane]
  std::vector<double> y_;        // [i, lane]
  SimdVector<double> k_;         // [packed (i, j), lane]: kernel, then Cholesky factor
  std::vector<double> z_;        // [i, lane]: L^-1 y
};

}  // namespace multimodal_nvs
