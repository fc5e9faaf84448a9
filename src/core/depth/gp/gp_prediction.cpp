// The per-pixel step of the local GP, kept in its own file because it is compiled with FMA
// contraction allowed (cmake/core.cmake): unlike the angle grid and the length-scale search it
// needs no bit-level agreement with the reference, and it is the hottest loop of the package.
#include "multimodal_nvs/core/depth/gp/gp_prediction.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <type_traits>
#include <vector>

namespace multimodal_nvs {
namespace {
constexpr int kMaxStackPixels = 64;
}  // namespace

namespace {

// kSize > 0 fixes the set size at compile time (radar sets are tiny: the loops unroll); 0 is the
// general case. Same arithmetic either way. `Real` is the precision of the exponentials and the
// substitution: float runs twice the lanes per SIMD instruction.
//
// The pixels come as runs (a set's segments of several rows, see PixelRun): blocks of up to
// kMaxStackPixels pixels are assembled across runs, so that a set whose segments average ~15
// pixels still fills the SIMD lanes and pays the per-block set-up once per block, not per segment.
// Every pixel's arithmetic is independent of the block it lands in.
template <int kSize, typename Real>
void predictBlocks(const double* packed_factor, const double* beta, const float* azimuth,
                   const float* elevation, int n, double length_scale, const LocalGpParams& params,
                   const PixelRun* runs, int run_count, double shift) {
  if (kSize > 0) n = kSize;
  const Real a2 = static_cast<Real>(params.amplitude * params.amplitude);
  const double prior = params.amplitude * params.amplitude + params.noise * params.noise;
  const Real scale = static_cast<Real>(-0.5 / (length_scale * length_scale));
  // Pixels are processed in blocks with the block index innermost, so the exponentials and the
  // forward substitution vectorise across pixels. w is row-major n x block.
  // Spare entries so that the exponentials run over whole SIMD packets (no scalar tail).
  constexpr std::size_t kPacket = 64 / sizeof(Real);
  thread_local SimdVector<Real> w;
  w.resize(std::size_t(n) * kMaxStackPixels + kPacket, Real(0));
  // The block's pieces: pixels [at, at + count) of the block are pixels [offset, offset + count)
  // of runs[run].
  struct Piece {
    int run, offset, count, at;
  };
  int run = 0, offset = 0;
  while (run < run_count) {
    Piece pieces[kMaxStackPixels];
    int piece_count = 0, m = 0;
    while (m < kMaxStackPixels && run < run_count) {
      const int take = std::min(kMaxStackPixels - m, runs[run].count - offset);
      if (take > 0) {
        pieces[piece_count++] = {run, offset, take, m};
        m += take;
        offset += take;
      }
      if (offset >= runs[run].count) {
        ++run;
        offset = 0;
      }
    }
    if (m == 0) break;
    // The pixel angles in the working precision: read in place when the block is one piece of
    // float angles (a library memcpy per segment was measurable), else gathered.
    Real az_copy[kMaxStackPixels], el_copy[kMaxStackPixels];
    const Real* paz = az_copy;
    const Real* pel = el_copy;
    bool in_place = false;
    if constexpr (std::is_same_v<Real, float>) {
      if (piece_count == 1) {
        paz = runs[pieces[0].run].az + pieces[0].offset;
        pel = runs[pieces[0].run].el + pieces[0].offset;
        in_place = true;
      }
    }
    if (!in_place) {
      for (int k = 0; k < piece_count; ++k) {
        const Piece& piece = pieces[k];
        const float* run_az = runs[piece.run].az + piece.offset;
        const float* run_el = runs[piece.run].el + piece.offset;
        for (int p = 0; p < piece.count; ++p) {
          az_copy[piece.at + p] = run_az[p];
          el_copy[piece.at + p] = run_el[p];
        }
      }
    }
    for (int i = 0; i < n; ++i) {
      Real* wi = w.data() + std::size_t(i) * m;
      const Real az = azimuth[i];
      const Real el = elevation[i];
      for (int p = 0; p < m; ++p) {
        const Real da = az - paz[p];
        const Real de = el - pel[p];
        wi[p] = (da * da + de * de) * scale;
      }
    }
    Eigen::Map<Eigen::Array<Real, Eigen::Dynamic, 1>> block(
        w.data(), (std::size_t(n) * m + kPacket - 1) & ~(kPacket - 1));
    block = block.exp() * a2;
    // Clear only the m accumulators in use.
    Real mean[kMaxStackPixels], norm2[kMaxStackPixels];
    std::fill_n(mean, m, Real(0));
    std::fill_n(norm2, m, Real(0));
    const double* row = packed_factor;
    for (int i = 0; i < n; ++i) {
      Real* wi = w.data() + std::size_t(i) * m;
      for (int j = 0; j < i; ++j) {
        const Real lij = static_cast<Real>(row[j]);
        const Real* wj = w.data() + std::size_t(j) * m;
        for (int p = 0; p < m; ++p)
          wi[p] -= lij * wj[p];
      }
      const Real inv_diag = static_cast<Real>(1.0 / row[i]);
      const Real bi = static_cast<Real>(beta[i]);
      for (int p = 0; p < m; ++p) {
        wi[p] *= inv_diag;
        mean[p] += wi[p] * bi;
        norm2[p] += wi[p] * wi[p];
      }
      row += i + 1;
    }
    for (int k = 0; k < piece_count; ++k) {
      const Piece& piece = pieces[k];
      float* mean_out = runs[piece.run].mean + piece.offset;
      float* var_out = runs[piece.run].variance + piece.offset;
      for (int p = 0; p < piece.count; ++p) {
        mean_out[p] = static_cast<float>(mean[piece.at + p] + shift);
        const double var = prior - norm2[piece.at + p];
        var_out[p] = static_cast<float>(var < 0.0 ? 0.0 : var);
      }
    }
  }
}

template <typename Real>
void predictWithPrecision(const double* packed_factor, const double* beta, const float* azimuth,
                          const float* elevation, int n, double length_scale,
                          const LocalGpParams& params, const PixelRun* runs, int run_count,
                          double shift) {
#define MMNVS_PREDICT(size)                                                                   \
  predictBlocks<size, Real>(packed_factor, beta, azimuth, elevation, n, length_scale, params, \
                            runs, run_count, shift)
  switch (n) {
    case 1:
      return MMNVS_PREDICT(1);
    case 2:
      return MMNVS_PREDICT(2);
    case 3:
      return MMNVS_PREDICT(3);
    case 4:
      return MMNVS_PREDICT(4);
    case 5:
      return MMNVS_PREDICT(5);
    case 6:
      return MMNVS_PREDICT(6);
    default:
      return MMNVS_PREDICT(0);
  }
#undef MMNVS_PREDICT
}

}  // namespace

void predictFromFactor(const double* packed_factor, const double* beta, const float* azimuth,
                       const float* elevation, int n, double length_scale,
                       const LocalGpParams& params, const PixelRun* runs, int run_count,
                       double shift, PredictionPrecision precision) {
  if (precision == PredictionPrecision::kSingle) {
    predictWithPrecision<float>(packed_factor, beta, azimuth, elevation, n, length_scale, params,
                                runs, run_count, shift);
  } else {
    predictWithPrecision<double>(packed_factor, beta, azimuth, elevation, n, length_scale, params,
                                 runs, run_count, shift);
  }
}

void predictFromFactor(const double* packed_factor, const double* beta, const float* azimuth,
                       const float* elevation, int n, double length_scale,
                       const LocalGpParams& params, const float* pixel_az, const float* pixel_el,
                       int pixels, double shift, float* mean_out, float* var_out,
                       PredictionPrecision precision) {
  const PixelRun run{pixel_az, pixel_el, mean_out, var_out, pixels};
  predictFromFactor(packed_factor, beta, azimuth, elevation, n, length_scale, params, &run, 1,
                    shift, precision);
}

}  // namespace multimodal_nvs
