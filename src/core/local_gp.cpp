#include "multimodal_nvs/core/local_gp.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "multimodal_nvs/core/errors.hpp"

namespace multimodal_nvs {
namespace {
constexpr double kLog2Pi = 1.8378770664093454835606594728112;
constexpr int kMaxStackPixels = 64;
// Up to this size the packed scalar Cholesky beats Eigen's dynamic-size LLT (no copies, no
// blocking overhead); beyond it Eigen's vectorised blocked factorisation wins.
constexpr int kPackedCholeskyMaxSize = 32;
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
  sq_dist_.resize(std::size_t(n) * (n + 1) / 2);
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
  const std::size_t packed = sq_dist_.size();
  packed_.resize(packed);
  Eigen::Map<Eigen::ArrayXd>(packed_.data(), packed) =
      (Eigen::Map<const Eigen::ArrayXd>(sq_dist_.data(), packed) * scale).exp() * a2;
  std::size_t k = 0;
  for (int i = 0; i < n_; ++i) {
    k += i;
    packed_[k++] += noise2;
  }
  if (n_ <= kPackedCholeskyMaxSize) return choleskyPacked(packed_.data(), n_);
  // Large sets (dense LiDAR): Eigen's blocked, vectorised LLT on a dense copy.
  dense_.resize(n_, n_);
  k = 0;
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j <= i; ++j) dense_(i, j) = packed_[k++];
  }
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(dense_);
  if (llt.info() != Eigen::Success) return false;
  k = 0;
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j <= i; ++j) packed_[k++] = dense_(i, j);
    if (!(dense_(i, i) > 0.0) || !std::isfinite(dense_(i, i))) return false;
  }
  return true;
}

bool choleskyPacked(double* a, int n) {
  // Row-oriented Cholesky on the packed lower triangle (row i holds i+1 values). Fails on a
  // non-positive or NaN pivot, as LAPACK's potrf does.
  double* row_i = a;
  for (int i = 0; i < n; ++i) {
    const double* row_j = a;
    for (int j = 0; j < i; ++j) {
      double sum = row_i[j];
      for (int k = 0; k < j; ++k) sum -= row_i[k] * row_j[k];
      row_i[j] = sum / row_j[j];
      row_j += j + 1;
    }
    double diag = row_i[i];
    for (int k = 0; k < i; ++k) diag -= row_i[k] * row_i[k];
    if (!(diag > 0.0) || !std::isfinite(diag)) return false;
    row_i[i] = std::sqrt(diag);
    row_i += i + 1;
  }
  return true;
}

void forwardSubstitutePacked(const double* l, int n, double* x) {
  const double* row = l;
  for (int i = 0; i < n; ++i) {
    double sum = x[i];
    for (int k = 0; k < i; ++k) sum -= row[k] * x[k];
    x[i] = sum / row[i];
    row += i + 1;
  }
}

double LocalGp::negLogMarginalLikelihood(double length_scale) {
  if (!factorize(length_scale)) return std::numeric_limits<double>::infinity();
  scratch_ = y_;
  forwardSubstitutePacked(packed_.data(), n_, scratch_.data());
  double quad = 0.0, log_det = 0.0;
  std::size_t diag = 0;
  for (int i = 0; i < n_; ++i) {
    quad += scratch_[i] * scratch_[i];
    diag += i;
    log_det += std::log(packed_[diag++]);
  }
  return 0.5 * quad + log_det + 0.5 * n_ * kLog2Pi;
}

double LocalGp::searchLengthScale() {
  return goldenSectionMinimize([this](double l) { return negLogMarginalLikelihood(l); },
                               params_.length_scale_min, params_.length_scale_max,
                               params_.tolerance, params_.max_iterations);
}

bool LocalGp::posterior(double length_scale, std::vector<double>& packed_factor,
                        std::vector<double>& beta) {
  if (!factorize(length_scale)) return false;
  beta = y_;
  forwardSubstitutePacked(packed_.data(), n_, beta.data());
  packed_factor = packed_;
  return true;
}

void predictFromFactor(const double* packed_factor, const double* beta, const float* azimuth,
                       const float* elevation, int n, double length_scale,
                       const LocalGpParams& params, const float* pixel_az, const float* pixel_el,
                       int pixels, double shift, float* mean_out, float* var_out) {
  const double a2 = params.amplitude * params.amplitude;
  const double prior = a2 + params.noise * params.noise;
  const double scale = -0.5 / (length_scale * length_scale);
  // Pixels are processed in blocks with the block index innermost, so the exponentials and the
  // forward substitution vectorise across pixels. w is row-major n x block.
  thread_local std::vector<double> w;
  w.resize(std::size_t(n) * kMaxStackPixels);
  for (int p0 = 0; p0 < pixels; p0 += kMaxStackPixels) {
    const int m = std::min(kMaxStackPixels, pixels - p0);
    double paz[kMaxStackPixels], pel[kMaxStackPixels];
    for (int p = 0; p < m; ++p) {
      paz[p] = pixel_az[p0 + p];
      pel[p] = pixel_el[p0 + p];
    }
    for (int i = 0; i < n; ++i) {
      double* wi = w.data() + std::size_t(i) * m;
      const double az = azimuth[i];
      const double el = elevation[i];
      for (int p = 0; p < m; ++p) {
        const double da = az - paz[p];
        const double de = el - pel[p];
        wi[p] = (da * da + de * de) * scale;
      }
    }
    Eigen::Map<Eigen::ArrayXd> block(w.data(), std::size_t(n) * m);
    block = block.exp() * a2;
    double mean[kMaxStackPixels] = {0.0};
    double norm2[kMaxStackPixels] = {0.0};
    const double* row = packed_factor;
    for (int i = 0; i < n; ++i) {
      double* wi = w.data() + std::size_t(i) * m;
      for (int j = 0; j < i; ++j) {
        const double lij = row[j];
        const double* wj = w.data() + std::size_t(j) * m;
        for (int p = 0; p < m; ++p) wi[p] -= lij * wj[p];
      }
      const double inv_diag = 1.0 / row[i];
      const double bi = beta[i];
      for (int p = 0; p < m; ++p) {
        wi[p] *= inv_diag;
        mean[p] += wi[p] * bi;
        norm2[p] += wi[p] * wi[p];
      }
      row += i + 1;
    }
    for (int p = 0; p < m; ++p) {
      mean_out[p0 + p] = static_cast<float>(mean[p] + shift);
      const double var = prior - norm2[p];
      var_out[p0 + p] = static_cast<float>(var < 0.0 ? 0.0 : var);
    }
  }
}

}  // namespace multimodal_nvs
