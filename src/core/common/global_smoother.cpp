#include "multimodal_nvs/core/common/global_smoother.hpp"

// Hand-written because it is image_guided's hot path: OpenCV's FastGlobalSmootherFilter took
// 85 ms of the model's ~107 ms on VoD radar at stride 2 (968x608, three planes, 2 cores), most of
// it recomputing the same elimination coefficients for each plane, allocating and converting per
// call. The arithmetic follows OpenCV's (opencv_contrib fgs_filter.cpp): weights -exp(-d/sigma)
// from a table over the squared BGR distance, the Thomas algorithm forward and back, lambda times
// the attenuation after each iteration; a plane is multiplied by the reciprocal of the pivot
// instead of divided by it, so results agree with OpenCV's to float rounding, not bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace multimodal_nvs {
namespace {

constexpr int kRowBlock = 4;      // rows solved together: independent chains for the pipeline
constexpr int kColumnChunk = 64;  // columns per task of the vertical pass (its scratch in cache)

/// -exp(-sqrt(i) / sigma) for every squared BGR distance i (OpenCV's table: 3 * 256 * 256).
/// Kept for the last sigma, so that a stream of frames builds it (196,608 exponentials) once.
std::shared_ptr<const std::vector<float>> weightTable(float sigma) {
  static std::mutex mutex;
  static float cached_sigma = 0.0f;
  static std::shared_ptr<const std::vector<float>> cached;
  const std::lock_guard<std::mutex> lock(mutex);
  if (cached && cached_sigma == sigma) return cached;
  auto table = std::make_shared<std::vector<float>>(3 * 256 * 256);
  for (std::size_t i = 0; i < table->size(); ++i)
    (*table)[i] = -std::exp(-std::sqrt(static_cast<float>(i)) / sigma);
  cached_sigma = sigma;
  cached = table;
  return cached;
}

inline int squaredDistance(const std::uint8_t* a, const std::uint8_t* b) {
  const int d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
  return d0 * d0 + d1 * d1 + d2 * d2;
}

struct Weights {
  cv::Mat horizontal;  // (r, c): between (r, c) and (r, c + 1); 0 in the last column
  cv::Mat vertical;    // (r, c): between (r, c) and (r + 1, c); 0 in the last row
};

Weights edgeWeights(const cv::Mat& guide, float sigma, ThreadPool& pool) {
  const std::shared_ptr<const std::vector<float>> cached_table = weightTable(sigma);
  const std::vector<float>& table = *cached_table;
  const int rows = guide.rows, cols = guide.cols;
  Weights w{cv::Mat(rows, cols, CV_32F), cv::Mat(rows, cols, CV_32F)};
  pool.parallelFor(
      rows,
      [&](long long r, int) {
        const std::uint8_t* g = guide.ptr<std::uint8_t>(static_cast<int>(r));
        const std::uint8_t* below =
            r + 1 < rows ? guide.ptr<std::uint8_t>(static_cast<int>(r) + 1) : nullptr;
        float* h = w.horizontal.ptr<float>(static_cast<int>(r));
        float* v = w.vertical.ptr<float>(static_cast<int>(r));
        for (int c = 0; c + 1 < cols; ++c)
          h[c] = table[squaredDistance(g + 3 * c, g + 3 * c + 3)];
        h[cols - 1] = 0.0f;
        for (int c = 0; c < cols; ++c)
          v[c] = below ? table[squaredDistance(g + 3 * c, below + 3 * c)] : 0.0f;
      },
      8);
  return w;
}

constexpr int kMaxPlanes = 4;

/// One horizontal solve of rows [r0, r0 + n), n <= kRowBlock, of every plane: the elimination
/// and the planes' forward substitution in one sweep (n * planes independent chains), then the
/// back substitution. `ratio`: scratch of cols * kRowBlock floats.
void horizontalBlock(const Weights& w, float* const* planes, int plane_count, int cols,
                     float lambda, int r0, int n, float* ratio) {
  const float* weight[kRowBlock];
  float* row[kRowBlock][kMaxPlanes];
  float previous[kRowBlock];
  for (int k = 0; k < n; ++k) {
    weight[k] = w.horizontal.ptr<float>(r0 + k);
    for (int p = 0; p < plane_count; ++p)
      row[k][p] = planes[p] + std::size_t(r0 + k) * cols;
    previous[k] = lambda * weight[k][0];
    const float inverse = 1.0f / (1.0f - previous[k]);
    ratio[k] = previous[k] * inverse;
    for (int p = 0; p < plane_count; ++p)
      row[k][p][0] *= inverse;
  }
  for (int c = 1; c < cols; ++c) {
    for (int k = 0; k < n; ++k) {
      const float current = lambda * weight[k][c];
      const float inverse =
          1.0f / ((1.0f - previous[k] - current) - ratio[(c - 1) * kRowBlock + k] * previous[k]);
      ratio[c * kRowBlock + k] = current * inverse;
      for (int p = 0; p < plane_count; ++p)
        row[k][p][c] = (row[k][p][c] - row[k][p][c - 1] * previous[k]) * inverse;
      previous[k] = current;
    }
  }
  for (int c = cols - 2; c >= 0; --c) {
    for (int k = 0; k < n; ++k) {
      const float q = ratio[c * kRowBlock + k];
      for (int p = 0; p < plane_count; ++p)
        row[k][p][c] -= q * row[k][p][c + 1];
    }
  }
}

/// One vertical solve of columns [c0, c1) of every plane, row by row (the columns vectorise):
/// elimination and forward substitution in one sweep down, back substitution in one sweep up.
/// `ratio`: scratch of rows * (c1 - c0) floats.
void verticalChunk(const Weights& w, float* const* planes, int plane_count, int cols, float lambda,
                   int c0, int c1, float* ratio) {
  const int rows = w.vertical.rows, width = c1 - c0;
  for (int r = 0; r < rows; ++r) {
    const float* __restrict weight = w.vertical.ptr<float>(r) + c0;
    const float* __restrict weight_above = r > 0 ? w.vertical.ptr<float>(r - 1) + c0 : nullptr;
    float* __restrict q = ratio + std::size_t(r) * width;
    const float* __restrict q_above = r > 0 ? q - width : nullptr;
    float inverse[kColumnChunk], coupling[kColumnChunk];
    for (int c = 0; c < width; ++c) {
      const float above = r > 0 ? lambda * weight_above[c] : 0.0f;
      const float current = lambda * weight[c];
      const float pivot = r > 0 ? (1.0f - above - current) - q_above[c] * above : 1.0f - current;
      inverse[c] = 1.0f / pivot;
      q[c] = current * inverse[c];
      coupling[c] = above;
    }
    for (int p = 0; p < plane_count; ++p) {
      float* __restrict x = planes[p] + std::size_t(r) * cols + c0;
      if (r == 0) {
        for (int c = 0; c < width; ++c)
          x[c] *= inverse[c];
      } else {
        const float* __restrict x_above = x - cols;
        for (int c = 0; c < width; ++c)
          x[c] = (x[c] - x_above[c] * coupling[c]) * inverse[c];
      }
    }
  }
  for (int r = rows - 2; r >= 0; --r) {
    const float* __restrict q = ratio + std::size_t(r) * width;
    for (int p = 0; p < plane_count; ++p) {
      float* __restrict x = planes[p] + std::size_t(r) * cols + c0;
      const float* __restrict x_below = x + cols;
      for (int c = 0; c < width; ++c)
        x[c] -= q[c] * x_below[c];
    }
  }
}

}  // namespace

void smoothAlongGuide(const cv::Mat& guide, std::vector<cv::Mat>& planes,
                      const GlobalSmootherParams& params, ThreadPool& pool) {
  if (guide.type() != CV_8UC3) throw std::invalid_argument("smoothAlongGuide: guide not CV_8UC3");
  for (const cv::Mat& plane : planes) {
    if (plane.type() != CV_32FC1 || plane.size() != guide.size()) {
      throw std::invalid_argument("smoothAlongGuide: planes must be CV_32FC1 of the guide's size");
    }
  }
  const int rows = guide.rows, cols = guide.cols;
  if (rows == 0 || cols == 0 || planes.empty()) return;
  if (planes.size() > std::size_t(kMaxPlanes)) {
    throw std::invalid_argument("smoothAlongGuide: at most 4 planes");
  }
  const Weights weights = edgeWeights(guide, static_cast<float>(params.sigma_color), pool);
  float* data[kMaxPlanes];
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (!planes[p].isContinuous()) planes[p] = planes[p].clone();
    data[p] = planes[p].ptr<float>(0);
  }
  const int plane_count = static_cast<int>(planes.size());
  // Per-worker scratch: a row block's ratios, a column chunk's (small enough to stay in cache).
  std::vector<std::vector<float>> scratch(pool.size());
  for (std::vector<float>& s : scratch)
    s.resize(std::max<std::size_t>(std::size_t(cols) * kRowBlock,
                                   std::size_t(rows) * std::min(cols, kColumnChunk)));
  const int row_blocks = (rows + kRowBlock - 1) / kRowBlock;
  const int column_chunks = (cols + kColumnChunk - 1) / kColumnChunk;
  float lambda = static_cast<float>(params.lambda);
  for (int iteration = 0; iteration < params.iterations; ++iteration) {
    pool.parallelFor(row_blocks, [&](long long b, int worker) {
      const int r0 = static_cast<int>(b) * kRowBlock;
      horizontalBlock(weights, data, plane_count, cols, lambda, r0, std::min(kRowBlock, rows - r0),
                      scratch[worker].data());
    });
    pool.parallelFor(column_chunks, [&](long long chunk, int worker) {
      const int c0 = static_cast<int>(chunk) * kColumnChunk;
      verticalChunk(weights, data, plane_count, cols, lambda, c0, std::min(cols, c0 + kColumnChunk),
                    scratch[worker].data());
    });
    lambda *= static_cast<float>(params.attenuation);
  }
}

}  // namespace multimodal_nvs
