#pragma once
// The local GP's algebra: hyperparameters, golden-section search, packed Cholesky, prediction.
#include <Eigen/Core>
#include <vector>

#include "multimodal_nvs/core/common/simd_buffer.hpp"

namespace multimodal_nvs {

/// log(2 pi): the constant of a Gaussian's negative log marginal likelihood (0.5 n log 2 pi), in
/// LocalGp's and the batched length-scale search's likelihoods alike.
inline constexpr double kLog2Pi = 1.8378770664093454835606594728112;

/// Hyperparameters of the local GP with marginal-likelihood length scale (reference defaults).
struct LocalGpParams {
  double amplitude = 25.0;        ///< a; kernel variance a^2
  double noise = 0.5;             ///< observation noise sigma, added as sigma^2 on the diagonal
  double length_scale_min = 0.1;  ///< degrees
  double length_scale_max = 10.0;
  double tolerance = 1e-3;  ///< golden-section stops when the bracket is this narrow
  int max_iterations = 64;

  double priorVariance() const { return amplitude * amplitude; }
  /// Throws InputError naming the bad parameter.
  void validate() const;
};

/// Golden-section minimisation on [lo, hi] with exactly the reference's evaluation sequence: the
/// likelihood can have several minima, so another sequence could settle in another one.
template <typename Objective>
double goldenSectionMinimize(Objective&& f, double lo, double hi, double tol, int max_iter);

/// GP regression on one neighbour set: positions (az, el) in degrees and shifted targets y. Holds
/// the workspace so that the ~20 likelihood evaluations of a length-scale search allocate nothing.
class LocalGp {
 public:
  explicit LocalGp(const LocalGpParams& params) : params_(params) {}

  /// Loads a neighbour set. Angles are float32 (as stored), promoted to double as the reference
  /// does.
  void setData(const float* azimuth, const float* elevation, const double* targets, int n);

  /// 0.5 y^T K^-1 y + 0.5 log det K + 0.5 n log(2 pi); +infinity when the Cholesky fails.
  double negLogMarginalLikelihood(double length_scale);
  /// Length scale minimising the negative log marginal likelihood (golden section).
  double searchLengthScale();

  /// Factorises K at `length_scale`; on success fills the lower Cholesky factor (packed by rows,
  /// n(n+1)/2 values) and beta = L^-1 y. Returns false when the Cholesky fails.
  bool posterior(double length_scale, std::vector<double>& packed_factor,
                 std::vector<double>& beta);

  int size() const { return n_; }

 private:
  bool factorize(double length_scale);

  LocalGpParams params_;
  int n_ = 0;
  std::vector<double> az_, el_, y_;
  SimdVector<double> sq_dist_;  // packed lower triangle, row-major (padded)
  SimdVector<double> packed_;   // K, then its Cholesky factor, packed like sq_dist_
  std::vector<double> scratch_;
  // Column-major n x n copy for sets above the unrolled size, in a buffer that only grows: an
  // Eigen::MatrixXd resized per set reallocated whenever n changed, in the one malloc arena the
  // tools and nodes share between threads (retainFreedMemory). VoD radar, exact GP, two threads:
  // the factorisation stage of its ~3,900 sets 0.93 -> 0.80 ms.
  std::vector<double> dense_storage_;
  Eigen::Map<Eigen::MatrixXd> denseOfSize(int n);
};

/// In-place Cholesky of a packed lower triangle (row i holds i+1 values); false on a non-positive
/// or NaN pivot, like LAPACK's potrf.
bool choleskyPacked(double* packed, int n);
/// In-place left-looking Cholesky of a column-major n x n matrix (lower triangle read and
/// written); its updates are contiguous AXPYs. False on a non-positive or NaN pivot.
bool choleskyColumns(double* column_major, int n);
/// Solves L x = b in place for a packed lower-triangular L.
void forwardSubstitutePacked(const double* packed, int n, double* x);

// ---------------------------------------------------------------------------------------------
template <typename Objective>
double goldenSectionMinimize(Objective&& f, double lo, double hi, double tol, int max_iter) {
  const double ratio = (std::sqrt(5.0) + 1.0) / 2.0;
  double a = lo, b = hi;
  double c = b - (b - a) / ratio;
  double d = a + (b - a) / ratio;
  double fc = f(c);
  double fd = f(d);
  for (int i = 0; i < max_iter; ++i) {
    if (std::abs(b - a) <= tol) break;
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - (b - a) / ratio;
      fc = f(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + (b - a) / ratio;
      fd = f(d);
    }
  }
  return fc < fd ? c : d;
}

}  // namespace multimodal_nvs
