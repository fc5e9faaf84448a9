#include "multimodal_nvs/core/depth/gp/local_gp.hpp"

#include "multimodal_nvs/core/depth/gp/length_scale_search.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace {
// Up to this size the packed scalar Cholesky beats Eigen's dynamic-size LLT (no copies, no
// blocking overhead); beyond it Eigen's vectorised blocked factorisation wins.
constexpr int kPackedCholeskyMaxSize = 32;
// Sizes up to this use the fully unrolled packed factorisation.
constexpr int kUnrolledCholeskyMaxSize = 8;
constexpr int kMaxPackedSize = kPackedCholeskyMaxSize;
// Length of a buffer rounded up to whole 8-double SIMD packets.
std::size_t paddedToPackets(std::size_t n) {
  return (n + 7) & ~std::size_t(7);
}
}  // namespace

void LocalGpParams::validate() const {
  auto fail = [](const std::string& what) { throw InputError("local GP parameter " + what); };
  if (!(amplitude > 0.0) || !std::isfinite(amplitude)) fail("amplitude must be > 0");
  if (!(noise > 0.0) || !std::isfinite(noise)) fail("noise must be > 0");
  if (!(length_scale_min > 0.0) || !(length_scale_max > length_scale_min) ||
      !std::isfinite(length_scale_max)) {
    fail("length_scale_min/max must satisfy 0 < min < max");
  }
  if (!(tolerance > 0.0)) fail("tolerance must be > 0");
  if (max_iterations < 0) fail("max_iterations must be >= 0");
}

void LocalGp::setData(const float* azimuth, const float* elevation, const double* targets, int n) {
  n_ = n;
  az_.assign(azimuth, azimuth + n);
  el_.assign(elevation, elevation + n);
  y_.assign(targets, targets + n);
  sq_dist_.assign(paddedToPackets(std::size_t(n) * (n + 1) / 2), 0.0);
  std::size_t k = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= i; ++j) {
      const double da = az_[i] - az_[j];
      const double de = el_[i] - el_[j];
      sq_dist_[k++] = da * da + de * de;
    }
  }
  scratch_.resize(n);
}

bool LocalGp::factorize(double length_scale) {
  const double a2 = params_.amplitude * params_.amplitude;
  const double noise2 = params_.noise * params_.noise;
  const double scale = -0.5 / (length_scale * length_scale);
  // All exponentials of the packed triangle at once: Eigen vectorises exp, std::exp does not.
  // sq_dist_ is padded to whole SIMD packets so that Eigen never falls back to scalar exp.
  const std::size_t padded = sq_dist_.size();
  packed_.resize(padded);
  Eigen::Map<Eigen::ArrayXd>(packed_.data(), padded) =
      (Eigen::Map<const Eigen::ArrayXd>(sq_dist_.data(), padded) * scale).exp() * a2;
  std::size_t k = 0;
  for (int i = 0; i < n_; ++i) {
    k += i;
    packed_[k++] += noise2;
  }
  if (n_ <= kUnrolledCholeskyMaxSize) return choleskyPacked(packed_.data(), n_);
  // Both dense paths read and write the lower triangle only (the upper one holds whatever an
  // earlier set left there).
  Eigen::Map<Eigen::MatrixXd> dense = denseOfSize(n_);
  k = 0;
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j <= i; ++j)
      dense(i, j) = packed_[k++];
  }
  if (n_ <= kPackedCholeskyMaxSize) {
    // Medium sets: column-major copy, so that the updates are contiguous AXPYs that vectorise.
    if (!choleskyColumns(dense.data(), n_)) return false;
    k = 0;
    for (int i = 0; i < n_; ++i) {
      for (int j = 0; j <= i; ++j)
        packed_[k++] = dense(i, j);
    }
    return true;
  }
  // Large sets (dense LiDAR): Eigen's blocked, vectorised LLT on a dense copy.
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(dense);
  if (llt.info() != Eigen::Success) return false;
  k = 0;
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j <= i; ++j)
      packed_[k++] = dense(i, j);
    if (!(dense(i, i) > 0.0) || !std::isfinite(dense(i, i))) return false;
  }
  return true;
}

Eigen::Map<Eigen::MatrixXd> LocalGp::denseOfSize(int n) {
  const std::size_t size = std::size_t(n) * std::size_t(n);
  if (dense_storage_.size() < size) dense_storage_.resize(size);
  return Eigen::Map<Eigen::MatrixXd>(dense_storage_.data(), n, n);
}

namespace {

// Row-oriented Cholesky on the packed lower triangle (row i holds i+1 values). Fails on a
// non-positive or NaN pivot, as LAPACK's potrf does. Reciprocals of the pivots turn the O(n^2)
// divisions into multiplications. kSize > 0 fixes the size at compile time so that the tiny
// matrices of radar neighbour sets are fully unrolled; the arithmetic is the same either way.
template <int kSize>
bool choleskyRows(double* a, int n) {
  if (kSize > 0) n = kSize;
  double inverse_diag[kMaxPackedSize];
  double* row_i = a;
  for (int i = 0; i < n; ++i) {
    const double* row_j = a;
    for (int j = 0; j < i; ++j) {
      double sum = row_i[j];
      for (int k = 0; k < j; ++k)
        sum -= row_i[k] * row_j[k];
      row_i[j] = sum * inverse_diag[j];
      row_j += j + 1;
    }
    double diag = row_i[i];
    for (int k = 0; k < i; ++k)
      diag -= row_i[k] * row_i[k];
    if (!(diag > 0.0) || !std::isfinite(diag)) return false;
    row_i[i] = std::sqrt(diag);
    inverse_diag[i] = 1.0 / row_i[i];
    row_i += i + 1;
  }
  return true;
}

}  // namespace

bool choleskyColumns(double* c, int n) {
  for (int j = 0; j < n; ++j) {
    double* __restrict column_j = c + std::size_t(j) * n;
    for (int k = 0; k < j; ++k) {
      const double l_jk = c[std::size_t(k) * n + j];
      const double* __restrict column_k = c + std::size_t(k) * n;
      for (int i = j; i < n; ++i)
        column_j[i] -= l_jk * column_k[i];
    }
    const double diag = column_j[j];
    if (!(diag > 0.0) || !std::isfinite(diag)) return false;
    const double pivot = std::sqrt(diag);
    const double inverse = 1.0 / pivot;
    column_j[j] = pivot;
    for (int i = j + 1; i < n; ++i)
      column_j[i] *= inverse;
  }
  return true;
}

bool choleskyPacked(double* a, int n) {
  switch (n) {
    case 1:
      return choleskyRows<1>(a, n);
    case 2:
      return choleskyRows<2>(a, n);
    case 3:
      return choleskyRows<3>(a, n);
    case 4:
      return choleskyRows<4>(a, n);
    case 5:
      return choleskyRows<5>(a, n);
    case 6:
      return choleskyRows<6>(a, n);
    case 7:
      return choleskyRows<7>(a, n);
    case 8:
      return choleskyRows<8>(a, n);
    default:
      return n <= kMaxPackedSize && choleskyRows<0>(a, n);
  }
}

void forwardSubstitutePacked(const double* l, int n, double* x) {
  const double* row = l;
  for (int i = 0; i < n; ++i) {
    double sum = x[i];
    for (int k = 0; k < i; ++k)
      sum -= row[k] * x[k];
    x[i] = sum / row[i];
    row += i + 1;
  }
}

double LocalGp::negLogMarginalLikelihood(double length_scale) {
  if (!factorize(length_scale)) return std::numeric_limits<double>::infinity();
  scratch_ = y_;
  forwardSubstitutePacked(packed_.data(), n_, scratch_.data());
  double quad = 0.0, log_det = 0.0, diag_product = 1.0;
  std::size_t diag = 0;
  for (int i = 0; i < n_; ++i) {
    quad += scratch_[i] * scratch_[i];
    diag += i;
    // One log per 16 factors instead of one per factor; 16 pivots cannot overflow a double.
    diag_product *= packed_[diag++];
    if ((i & 15) == 15) {
      log_det += std::log(diag_product);
      diag_product = 1.0;
    }
  }
  log_det += std::log(diag_product);
  return 0.5 * quad + log_det + 0.5 * n_ * kLog2Pi;
}

double LocalGp::searchLengthScale() {
  if (n_ >= 3 && n_ <= LengthScaleSearch::kMaxBatchedSize) {
    // The same code the batched model path runs, so a set's length scale never depends on the
    // path that computed it.
    LengthScaleSearch batch(params_);
    std::vector<float> az(az_.begin(), az_.end()), el(el_.begin(), el_.end());
    const float* paz = az.data();
    const float* pel = el.data();
    const double* py = y_.data();
    double length_scale;
    batch.search(n_, 1, &paz, &pel, &py, &length_scale);
    return length_scale;
  }
  return goldenSectionMinimize([this](double l) { return negLogMarginalLikelihood(l); },
                               params_.length_scale_min, params_.length_scale_max,
                               params_.tolerance, params_.max_iterations);
}

bool LocalGp::posterior(double length_scale, std::vector<double>& packed_factor,
                        std::vector<double>& beta) {
  if (!factorize(length_scale)) return false;
  beta = y_;
  forwardSubstitutePacked(packed_.data(), n_, beta.data());
  packed_factor.assign(packed_.begin(), packed_.begin() + std::size_t(n_) * (n_ + 1) / 2);
  return true;
}

}  // namespace multimodal_nvs
