#include "multimodal_nvs/core/depth/gp/length_scale_search.hpp"

#include <immintrin.h>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace multimodal_nvs {
namespace {

// The lanes' Cholesky pivots and divisions as whole-register operations (GCC vector types,
// element-wise IEEE, so each lane computes the scalar expression's bits): written as loops over
// the lanes GCC 12 keeps them scalar, a chain of long latencies per pivot, and a vector load of
// values just stored lane by lane stalls on store forwarding.

/// One 64-byte register of Scalar (BasicLengthScaleSearch's lanes).
template <typename Scalar>
struct LaneRegister {
  typedef Scalar Type __attribute__((vector_size(64)));
};

/// Each lane's correctly rounded square root, in place: one instruction with AVX-512 (GCC has no
/// generic vector square root, and a lane loop stays scalar while sqrt may set errno). By
/// reference: a 64-byte vector passed by value changes the ABI on builds without AVX-512.
template <typename Scalar>
void takeSquareRoots(typename LaneRegister<Scalar>::Type& v) {
  using Register = typename LaneRegister<Scalar>::Type;
#ifdef __AVX512F__
  if constexpr (sizeof(Scalar) == sizeof(double)) {
    v = reinterpret_cast<Register>(_mm512_sqrt_pd(reinterpret_cast<__m512d>(v)));
  } else {
    v = reinterpret_cast<Register>(_mm512_sqrt_ps(reinterpret_cast<__m512>(v)));
  }
#else
  for (int lane = 0; lane < int(sizeof(Register) / sizeof(Scalar)); ++lane)
    v[lane] = std::sqrt(v[lane]);
#endif
}

/// pivot = sqrt(diag) and inverse = 1 / pivot in every lane where diag is positive and finite;
/// elsewhere the pivot is 1 and the lane is marked failed.
template <typename Scalar>
void choleskyPivots(const Scalar* diag, Scalar* pivot, Scalar* inverse, bool* failed) {
  using Register = typename LaneRegister<Scalar>::Type;
  constexpr int kLanes = sizeof(Register) / sizeof(Scalar);
  Register d;
  std::memcpy(&d, diag, sizeof d);
  const auto good = (d > Scalar(0)) & (d <= std::numeric_limits<Scalar>::max());
  const Register one = Register{} + Scalar(1);
  Register p = good ? d : one;
  takeSquareRoots<Scalar>(p);
  const Register reciprocal = one / p;
  std::memcpy(pivot, &p, sizeof p);
  std::memcpy(inverse, &reciprocal, sizeof reciprocal);
  for (int lane = 0; lane < kLanes; ++lane)
    failed[lane] = failed[lane] || good[lane] == 0;
}

/// out[lane] = a[lane] / b[lane]
template <typename Scalar>
void quotients(const Scalar* a, const Scalar* b, Scalar* out) {
  using Register = typename LaneRegister<Scalar>::Type;
  Register x, y;
  std::memcpy(&x, a, sizeof x);
  std::memcpy(&y, b, sizeof y);
  const Register q = x / y;
  std::memcpy(out, &q, sizeof q);
}
}  // namespace

template <typename Scalar>
void BasicLengthScaleSearch<Scalar>::load(int n, int lanes, const float* const* az,
                                          const float* const* el, const double* const* y) {
  constexpr int L = kLanes;
  n_ = n;
  const std::size_t packed = std::size_t(n) * (n + 1) / 2;
  sq_dist_.assign(packed * L, Scalar(0));
  y_.assign(std::size_t(n) * L, Scalar(0));
  k_.resize(packed * L);
  z_.resize(std::size_t(n) * L);
  // Unused lanes repeat lane 0, so they stay numerically harmless.
  for (int lane = 0; lane < L; ++lane) {
    const int s = lane < lanes ? lane : 0;
    std::size_t k = 0;
    for (int i = 0; i < n; ++i) {
      const double azi = az[s][i], eli = el[s][i];
      for (int j = 0; j <= i; ++j, ++k) {
        const double da = azi - double(az[s][j]);
        const double de = eli - double(el[s][j]);
        sq_dist_[k * L + lane] = static_cast<Scalar>(da * da + de * de);
      }
      y_[std::size_t(i) * L + lane] = static_cast<Scalar>(y[s][i]);
    }
  }
}

template <typename Scalar>
void BasicLengthScaleSearch<Scalar>::negLogMarginalLikelihood(const double* length_scale,
                                                              double* out) {
  constexpr int L = kLanes;
  const int n = n_;
  const std::size_t packed = std::size_t(n) * (n + 1) / 2;
  const Scalar a2 = static_cast<Scalar>(params_.amplitude * params_.amplitude);
  const Scalar noise2 = static_cast<Scalar>(params_.noise * params_.noise);
  Scalar scale[L];
  for (int lane = 0; lane < L; ++lane)
    scale[lane] = static_cast<Scalar>(-0.5 / (length_scale[lane] * length_scale[lane]));
  for (std::size_t k = 0; k < packed; ++k) {
    for (int lane = 0; lane < L; ++lane)
      k_[k * L + lane] = sq_dist_[k * L + lane] * scale[lane];
  }
  Eigen::Map<Eigen::Array<Scalar, Eigen::Dynamic, 1>> kernel(k_.data(), packed * L);
  kernel = kernel.exp() * a2;

  // Row-oriented Cholesky with reciprocal pivots, lane-parallel; a failed lane keeps going on a
  // harmless pivot of 1 and reports +inf.
  bool failed[L] = {false};
  Scalar inverse_diag[kMaxBatchedSize][L];
  Scalar* row_i = k_.data();
  for (int i = 0; i < n; ++i) {
    for (int lane = 0; lane < L; ++lane)
      row_i[i * L + lane] += noise2;
    const Scalar* row_j = k_.data();
    for (int j = 0; j < i; ++j) {
      Scalar sum[L];
      for (int lane = 0; lane < L; ++lane)
        sum[lane] = row_i[j * L + lane];
      for (int k = 0; k < j; ++k) {
        for (int lane = 0; lane < L; ++lane)
          sum[lane] -= row_i[k * L + lane] * row_j[k * L + lane];
      }
      for (int lane = 0; lane < L; ++lane)
        row_i[j * L + lane] = sum[lane] * inverse_diag[j][lane];
      row_j += (j + 1) * L;
    }
    Scalar diag[L];
    for (int lane = 0; lane < L; ++lane)
      diag[lane] = row_i[i * L + lane];
    for (int k = 0; k < i; ++k) {
      for (int lane = 0; lane < L; ++lane)
        diag[lane] -= row_i[k * L + lane] * row_i[k * L + lane];
    }
    choleskyPivots(diag, row_i + std::size_t(i) * L, inverse_diag[i], failed);
    row_i += (i + 1) * L;
  }

  // z = L^-1 y (forward substitution dividing by the pivot, as LocalGp does), quad = |z|^2,
  // log det = sum of logs of products of up to 16 pivots (in double: 16 float pivots of a kernel
  // with amplitude >= 1e-3 and noise >= 1e-6 can underflow a float).
  Scalar quad[L] = {Scalar(0)};
  double log_det[L] = {0.0}, product[L];
  for (int lane = 0; lane < L; ++lane)
    product[lane] = 1.0;
  const Scalar* row = k_.data();
  for (int i = 0; i < n; ++i) {
    Scalar sum[L];
    for (int lane = 0; lane < L; ++lane)
      sum[lane] = y_[std::size_t(i) * L + lane];
    for (int k = 0; k < i; ++k) {
      for (int lane = 0; lane < L; ++lane)
        sum[lane] -= row[k * L + lane] * z_[std::size_t(k) * L + lane];
    }
    Scalar* z = z_.data() + std::size_t(i) * L;
    quotients(sum, row + std::size_t(i) * L, z);
    for (int lane = 0; lane < L; ++lane) {
      quad[lane] += z[lane] * z[lane];
      product[lane] *= row[i * L + lane];
    }
    if ((i & 15) == 15) {
      for (int lane = 0; lane < L; ++lane) {
        log_det[lane] += std::log(product[lane]);
        product[lane] = 1.0;
      }
    }
    row += (i + 1) * L;
  }
  for (int lane = 0; lane < L; ++lane) {
    log_det[lane] += std::log(product[lane]);
    out[lane] = failed[lane] ? std::numeric_limits<double>::infinity()
                             : 0.5 * double(quad[lane]) + log_det[lane] + 0.5 * n * kLog2Pi;
  }
}

template <typename Scalar>
void BasicLengthScaleSearch<Scalar>::search(int n, int lanes, const float* const* az,
                                            const float* const* el, const double* const* y,
                                            double* length_scale) {
  constexpr int L = kLanes;
  load(n, lanes, az, el, y);
  // goldenSectionMinimize (local_gp.hpp), one bracket per lane. All lanes share lo, hi and tol,
  // so they take the same number of steps; only which end moves differs per lane.
  const double ratio = (std::sqrt(5.0) + 1.0) / 2.0;
  double a[L], b[L], c[L], d[L], fc[L], fd[L];
  bool done[L];
  for (int lane = 0; lane < L; ++lane) {
    a[lane] = params_.length_scale_min;
    b[lane] = params_.length_scale_max;
    c[lane] = b[lane] - (b[lane] - a[lane]) / ratio;
    d[lane] = a[lane] + (b[lane] - a[lane]) / ratio;
    done[lane] = lane >= lanes;
  }
  negLogMarginalLikelihood(c, fc);
  negLogMarginalLikelihood(d, fd);
  double probe[L], f[L];
  bool moved_hi[L];
  for (int iteration = 0; iteration < params_.max_iterations; ++iteration) {
    bool any = false;
    for (int lane = 0; lane < L; ++lane) {
      if (!done[lane] && std::abs(b[lane] - a[lane]) <= params_.tolerance) done[lane] = true;
      if (done[lane]) {
        probe[lane] = c[lane];  // evaluated but ignored
        continue;
      }
      any = true;
      moved_hi[lane] = fc[lane] < fd[lane];
      if (moved_hi[lane]) {
        b[lane] = d[lane];
        d[lane] = c[lane];
        fd[lane] = fc[lane];
        c[lane] = b[lane] - (b[lane] - a[lane]) / ratio;
        probe[lane] = c[lane];
      } else {
        a[lane] = c[lane];
        c[lane] = d[lane];
        fc[lane] = fd[lane];
        d[lane] = a[lane] + (b[lane] - a[lane]) / ratio;
        probe[lane] = d[lane];
      }
    }
    if (!any) break;
    negLogMarginalLikelihood(probe, f);
    for (int lane = 0; lane < L; ++lane) {
      if (done[lane]) continue;
      (moved_hi[lane] ? fc : fd)[lane] = f[lane];
    }
  }
  for (int lane = 0; lane < lanes; ++lane)
    length_scale[lane] = fc[lane] < fd[lane] ? c[lane] : d[lane];
}

template class BasicLengthScaleSearch<double>;
template class BasicLengthScaleSearch<float>;

}  // namespace multimodal_nvs
