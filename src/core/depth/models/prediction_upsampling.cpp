#include "multimodal_nvs/core/depth/models/prediction_upsampling.hpp"

#include <algorithm>
#include <stdexcept>

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

void UpsampledPredictions::prepare(const PixelPredictions& coarse, const StrideGrid& coarse_grid,
                                   const StrideGrid& grid, int factor, ThreadPool& pool) {
  rows_ = grid.rows();
  cols_ = grid.cols();
  coarse_rows_ = coarse_grid.rows();
  factor_ = factor;
  const int cols = cols_, coarse_cols = coarse_grid.cols();
  std::vector<int> lo(cols), hi(cols);
  std::vector<float> t(cols);
  for (int c = 0; c < cols; ++c) {
    const Between b = between(c, factor, coarse_cols);
    lo[c] = b.lo;
    hi[c] = b.hi;
    t[c] = b.t;
  }
  const std::size_t wide = std::size_t(coarse_rows_) * cols;
  wide_inverse_.resize(wide);
  wide_variance_.resize(wide);
  std::vector<std::vector<float>> inverse_rows(pool.size(), std::vector<float>(coarse_cols));
  pool.parallelFor(
      coarse_rows_,
      [&](long long r, int worker) {
        const std::size_t in = std::size_t(r) * coarse_cols, at = std::size_t(r) * cols;
        float* inverse = inverse_rows[worker].data();
        reciprocals(coarse.mean.data() + in, coarse_cols, inverse);
        expandRow(inverse, lo.data(), hi.data(), t.data(), cols, wide_inverse_.data() + at);
        expandRow(coarse.variance.data() + in, lo.data(), hi.data(), t.data(), cols,
                  wide_variance_.data() + at);
      },
      4);
}

void UpsampledPredictions::meanRow(int row, float* out) const {
  const Between b = between(row, factor_, coarse_rows_);
  // Inverse depth: affine in the image along a plane (the road).
  lerpRows<true>(wide_inverse_.data() + std::size_t(b.lo) * cols_,
                 wide_inverse_.data() + std::size_t(b.hi) * cols_, b.t, cols_, out);
}

void UpsampledPredictions::varianceRow(int row, float* out) const {
  const Between b = between(row, factor_, coarse_rows_);
  lerpRows<false>(wide_variance_.data() + std::size_t(b.lo) * cols_,
                  wide_variance_.data() + std::size_t(b.hi) * cols_, b.t, cols_, out);
}

void upsamplePredictions(const PixelPredictions& coarse, const StrideGrid& coarse_grid,
                         const StrideGrid& grid, int factor, ThreadPool& pool,
                         PixelPredictions& out) {
  UpsampledPredictions upsampled;
  upsampled.prepare(coarse, coarse_grid, grid, factor, pool);
  const int cols = upsampled.cols();
  out.mean.resize(std::size_t(upsampled.rows()) * cols);
  out.variance.resize(out.mean.size());
  pool.parallelFor(
      upsampled.rows(),
      [&](long long row, int) {
        const std::size_t at = std::size_t(row) * cols;
        upsampled.meanRow(static_cast<int>(row), out.mean.data() + at);
        upsampled.varianceRow(static_cast<int>(row), out.variance.data() + at);
      },
      16);
}

PredictionRows::PredictionRows(const PixelPredictions& stored, int rows, int cols)
    : stored_(&stored), rows_(rows), cols_(cols) {
  const std::size_t n = std::size_t(std::max(rows, 0)) * std::size_t(std::max(cols, 0));
  if (stored.mean.size() != n || stored.variance.size() != n)
    throw std::invalid_argument("PredictionRows: the prediction is not of rows x cols");
}

PredictionRows::PredictionRows(const UpsampledPredictions& upsampled)
    : upsampled_(&upsampled), rows_(upsampled.rows()), cols_(upsampled.cols()) {}

const float* PredictionRows::mean(int row, float* scratch) const {
  if (stored_ != nullptr) return stored_->mean.data() + std::size_t(row) * cols_;
  upsampled_->meanRow(row, scratch);
  return scratch;
}

const float* PredictionRows::variance(int row, float* scratch) const {
  if (stored_ != nullptr) return stored_->variance.data() + std::size_t(row) * cols_;
  upsampled_->varianceRow(row, scratch);
  return scratch;
}

}  // namespace multimodal_nvs
