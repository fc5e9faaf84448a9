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
/// its batch: batching only fills the lanes of an AVX-512 register with useful work.
/// Used for sets of 3..kMaxBatchedSize samples; two-sample sets need the reference-exact path and
/// one-sample sets need no likelihood at all (see local_gp_model.cpp).
///
/// `Scalar` is the arithmetic of the likelihood (the bracket itself is always double). double: the
/// exact models (the reference computes in float64). float: twice the lanes, for models with no
/// parity to keep (ground_gp's residual GP, whose small amplitude keeps its kernels well
/// conditioned).
template <typename Scalar>
class BasicLengthScaleSearch {
 public:
  /// One 64-byte AVX-512 register of Scalar.
  static constexpr int kLanes = 64 / static_cast<int>(sizeof(Scalar));
  static constexpr int kMaxBatchedSize = 32;

  explicit BasicLengthScaleSearch(const LocalGpParams& params) : params_(params) {}

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
  std::vector<Scalar> sq_dist_;  // [packed (i, j), lane]
  std::vector<Scalar> y_;        // [i, lane]
  SimdVector<Scalar> k_;         // [packed (i, j), lane]: kernel, then Cholesky factor
  std::vector<Scalar> z_;        // [i, lane]: L^-1 y
};

using LengthScaleSearch = BasicLengthScaleSearch<double>;
using SingleLengthScaleSearch = BasicLengthScaleSearch<float>;

extern template class BasicLengthScaleSearch<double>;
extern template class BasicLengthScaleSearch<float>;

}  // namespace multimodal_nvs
