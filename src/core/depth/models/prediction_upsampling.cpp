#include "multimodal_nvs/core/depth/models/prediction_upsampling.hpp"

#include <algorithm>

namespace multimodal_nvs {
namespace {

// The passes are functions of their own with restrict pointers so that GCC vectorises them.

void reciprocals(const float* __restrict in, int count, float* __restrict out) {
  for (int i = 0; i < count; ++i)
    out[i] = 1.0f / in[i];
}

void lerpRows(const float* __restrict a, const float* __restrict b, float t, int count,
              float* __restrict out) {
  for (int i = 0; i < count; ++i)
    out[i] = (1.0f - t) * a[i] + t * b[i];
}

/// out[c] = (1 - t[c]) in[lo[c]] + t[c] in[hi[c]], or its reciprocal.
template <bool kReciprocal>
void expandRow(const float* __restrict in, const int* __restrict lo, const int* __restrict hi,
               const float* __restrict t, int cols, float* __restrict out) {
  for (int c = 0; c < cols; ++c) {
    const float value = (1.0f - t[c]) * in[lo[c]] + t[c] * in[hi[c]];
    out[c] = kReciprocal ? 1.0f / value : value;
  }
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
                         std::vector<float>& inverse_scratch, PixelPredictions& out) {
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
  std::vector<float>& inverse = inverse_scratch;
  inverse.resize(coarse.mean.size());
  pool.parallelFor(
      coarse_rows,
      [&](long long r, int) {
        const std::size_t i = std::size_t(r) * coarse_cols;
        reciprocals(coarse.mean.data() + i, coarse_cols, inverse.data() + i);
      },
      16);
  // Each output row: the two coarse rows blended, then spread over the output columns.
  std::vector<std::vector<float>> blended(pool.size(), std::vector<float>(2 * coarse_cols));
  pool.parallelFor(
      rows,
      [&](long long row, int worker) {
        const Between b = between(static_cast<int>(row), factor, coarse_rows);
        float* inverse_row = blended[worker].data();
        float* variance_row = inverse_row + coarse_cols;
        lerpRows(inverse.data() + std::size_t(b.lo) * coarse_cols,
                 inverse.data() + std::size_t(b.hi) * coarse_cols, b.t, coarse_cols, inverse_row);
        lerpRows(coarse.variance.data() + std::size_t(b.lo) * coarse_cols,
                 coarse.variance.data() + std::size_t(b.hi) * coarse_cols, b.t, coarse_cols,
                 variance_row);
        const std::size_t at = std::size_t(row) * cols;
        expandRow<true>(inverse_row, lo.data(), hi.data(), t.data(), cols, out.mean.data() + at);
        expandRow<false>(variance_row, lo.data(), hi.data(), t.data(), cols,
                         out.variance.data() + at);
      },
      16);
}

}  // namespace multimodal_nvs
