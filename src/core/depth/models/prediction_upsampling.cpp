#include "multimodal_nvs/core/depth/models/prediction_upsampling.hpp"

#include <algorithm>

namespace multimodal_nvs {
namespace {

// The passes are functions of their own with restrict pointers so that GCC vectorises them.

void reciprocals(const float* __restrict in, int count, float* __restrict out) {
  for (int i = 0; i < count; ++i)
    out[i] = 1.0f / in[i];
}

/// out[i] = (1 - t) a[i] + t b[i], or its reciprocal.
template <bool kReciprocal>
void lerpRows(const float* __restrict a, const float* __restrict b, float t, int count,
              float* __restrict out) {
  for (int i = 0; i < count; ++i) {
    const float value = (1.0f - t) * a[i] + t * b[i];
    out[i] = kReciprocal ? 1.0f / value : value;
  }
}

/// out[c] = (1 - t[c]) in[lo[c]] + t[c] in[hi[c]].
void expandRow(const float* __restrict in, const int* __restrict lo, const int* __restrict hi,
               const float* __restrict t, int cols, float* __restrict out) {
  for (int c = 0; c < cols; ++c)
    out[c] = (1.0f - t[c]) * in[lo[c]] + t[c] * in[hi[c]];
}

/// The two coarse indices around output index i and the weight of the second.
struct Between {
  int lo, hi;
  float t;
};
Between between(int i, int factor, int coarse_count) {
  const int lo = std::min(i / factor, coarse_count - 1);
  const int hi = std::min(lo + 1, coarse_count - 1);
  return {lo, hi, hi == lo ? 0.0f : float(i - lo * factor) / float(factor)};
}

}  // namespace

void upsamplePredictions(const PixelPredictions& coarse, const StrideGrid& coarse_grid,
                         const StrideGrid& grid, int factor, ThreadPool& pool,
                         std::vector<float>& scratch, PixelPredictions& out) {
  const int rows = grid.rows(), cols = grid.cols();
  const int coarse_rows = coarse_grid.rows(), coarse_cols = coarse_grid.cols();
  out.mean.resize(std::size_t(rows) * cols);
  out.variance.resize(out.mean.size());
  std::vector<int> lo(cols), hi(cols);
  std::vector<float> t(cols);
  for (int c = 0; c < cols; ++c) {
    const Between b = between(c, factor, coarse_cols);
    lo[c] = b.lo;
    hi[c] = b.hi;
    t[c] = b.t;
  }
  // Each coarse row spread over the output columns once (inverse depth and variance), then each
  // output row blended from two of those: the index gathers run on a factor fewer rows.
  const std::size_t wide = std::size_t(coarse_rows) * cols;
  scratch.resize(2 * wide);
  float* const wide_inverse = scratch.data();
  float* const wide_variance = wide_inverse + wide;
  std::vector<std::vector<float>> inverse_rows(pool.size(), std::vector<float>(coarse_cols));
  pool.parallelFor(
      coarse_rows,
      [&](long long r, int worker) {
        const std::size_t in = std::size_t(r) * coarse_cols, at = std::size_t(r) * cols;
        float* inverse = inverse_rows[worker].data();
        reciprocals(coarse.mean.data() + in, coarse_cols, inverse);
        expandRow(inverse, lo.data(), hi.data(), t.data(), cols, wide_inverse + at);
        expandRow(coarse.variance.data() + in, lo.data(), hi.data(), t.data(), cols,
                  wide_variance + at);
      },
      4);
  pool.parallelFor(
      rows,
      [&](long long row, int) {
        const Between b = between(static_cast<int>(row), factor, coarse_rows);
        const std::size_t at = std::size_t(row) * cols;
        // Inverse depth: affine in the image along a plane (the road).
        lerpRows<true>(wide_inverse + std::size_t(b.lo) * cols,
                       wide_inverse + std::size_t(b.hi) * cols, b.t, cols, out.mean.data() + at);
        lerpRows<false>(wide_variance + std::size_t(b.lo) * cols,
                        wide_variance + std::size_t(b.hi) * cols, b.t, cols,
                        out.variance.data() + at);
      },
      16);
}

}  // namespace multimodal_nvs
