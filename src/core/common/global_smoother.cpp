#include "multimodal_nvs/core/common/global_smoother.hpp"

#include "multimodal_nvs/core/common/lane_transpose.hpp"
#include "multimodal_nvs/core/common/simd_buffer.hpp"

// Hand-written because it is image_guided's hot path: OpenCV's FastGlobalSmootherFilter took
// 85 ms of the model's ~107 ms on VoD radar at stride 2 (968x608, three planes, 2 cores), most of
// it recomputing the same elimination coefficients for each plane, allocating and converting per
// call. The arithmetic follows OpenCV's (opencv_contrib fgs_filter.cpp): weights -exp(-d/sigma)
// from a table over the squared BGR distance, the Thomas algorithm forward and back, lambda times
// the attenuation after each iteration; a plane is multiplied by the reciprocal of the pivot
// instead of divided by it, so results agree with OpenCV's to float rounding, not bit for bit.
// Where the time goes (perf, VoD 1936x1216, three planes): a row's solve is a chain of dependent
// divisions, so rows are solved eight at a time in vector lanes (transposed in and out); a
// column's solve steps a whole image row per row, which no hardware prefetcher follows, so the
// vertical sweeps prefetch a few rows ahead. Both keep every value's arithmetic as it was.
#include <immintrin.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace multimodal_nvs {
namespace {

constexpr int kColumnChunk = 128;  // columns per task of the vertical pass (its scratch in cache)
constexpr int kPrefetchRows = 4;   // how far ahead the vertical sweeps prefetch

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

/// out[i] = squaredDistance(a + 3 i, b + 3 i) for i < count. A function of its own with restrict
/// pointers: inline in the lambda the stores may alias its captured sizes and GCC keeps it scalar.
void squaredDistances(const std::uint8_t* __restrict a, const std::uint8_t* __restrict b, int count,
                      int* __restrict out) {
  for (int i = 0; i < count; ++i)
    out[i] = squaredDistance(a + 3 * i, b + 3 * i);
}

/// out[i] = table[index[i]] for i < count. The weight table is 768 kB and most look-ups miss L1:
/// with AVX-512 sixteen go out as one gather and are in flight together, where the scalar loop
/// (GCC 12 does not emit gathers for it) had one or two. The same values either way.
void lookUp(const float* __restrict table, const int* __restrict index, int count,
            float* __restrict out) {
  int i = 0;
#ifdef __AVX512F__
  for (; i + 16 <= count; i += 16) {
    const __m512i at = _mm512_loadu_si512(index + i);
    _mm512_storeu_ps(out + i, _mm512_i32gather_ps(at, table, sizeof(float)));
  }
#endif
  for (; i < count; ++i)
    out[i] = table[index[i]];
}

struct Weights {
  // Between (r, c) and (r, c + 1), 0 in the last column, in lanes: block b of rows [8b, 8b + 8)
  // holds columns [b * cols, (b + 1) * cols); rows past the image are 0. Every lane is written
  // (rowsToLanes pads the last block), so the buffer is not zeroed first (9 MB at VoD's size).
  struct Release {  // the buffer comes from SimdVector's allocator, without construction
    void operator()(float* p) const { AlignedAllocator<float>().deallocate(p, 0); }
  };
  std::unique_ptr<float[], Release> horizontal;
  Lanes* horizontalLanes() const { return reinterpret_cast<Lanes*>(horizontal.get()); }
  cv::Mat vertical;  // (r, c): between (r, c) and (r + 1, c); 0 in the last row
};

Weights edgeWeights(const cv::Mat& guide, float sigma, bool vertical_edges, ThreadPool& pool) {
  const std::shared_ptr<const std::vector<float>> cached_table = weightTable(sigma);
  const float* table = cached_table->data();
  const int rows = guide.rows, cols = guide.cols;
  const int blocks = (rows + kLaneCount - 1) / kLaneCount;
  Weights w{decltype(Weights::horizontal)(
                AlignedAllocator<float>().allocate(std::size_t(blocks) * cols * kLaneCount)),
            cv::Mat(rows, cols, CV_32F)};
  // Per worker: a row's squared distances to the right and below, a block's horizontal weights.
  std::vector<std::vector<int>> distances(pool.size(), std::vector<int>(2 * std::size_t(cols)));
  std::vector<std::vector<float>> block_rows(pool.size(),
                                             std::vector<float>(kLaneCount * std::size_t(cols)));
  pool.parallelFor(blocks, [&](long long b, int worker) {
    Lanes* lanes = w.horizontalLanes() + std::size_t(b) * cols;
    // The squared distances first (a loop that vectorises), then the table look-ups; the block's
    // horizontal weights row by row, then transposed into lanes.
    int* right = distances[worker].data();
    int* down = right + cols;
    float* horizontal = block_rows[worker].data();
    const int r0 = static_cast<int>(b) * kLaneCount, row_count = std::min(kLaneCount, rows - r0);
    for (int k = 0; k < row_count; ++k) {
      const int r = r0 + k;
      const std::uint8_t* g = guide.ptr<std::uint8_t>(r);
      squaredDistances(g, g + 3, cols - 1, right);
      lookUp(table, right, cols - 1, horizontal + std::size_t(k) * cols);
      horizontal[std::size_t(k) * cols + cols - 1] = 0.0f;
      float* v = w.vertical.ptr<float>(r);
      if (r + 1 == rows) {
        std::fill(v, v + cols, 0.0f);
        continue;
      }
      if (!vertical_edges) {  // the weight of equal colours
        std::fill(v, v + cols, table[0]);
        continue;
      }
      squaredDistances(g, guide.ptr<std::uint8_t>(r + 1), cols, down);
      lookUp(table, down, cols, v);
    }
    rowsToLanes(horizontal, cols, row_count, cols, lanes);
  });
  return w;
}

constexpr int kMaxPlanes = 4;

/// One horizontal solve of kBlocks lane blocks from `b` (rows [8b, 8b + 8 kBlocks) that exist) of
/// kPlanes planes, 8 kBlocks rows at once: the rows are transposed into lanes (`x`: kBlocks *
/// kPlanes * cols lanes of scratch, `ratio`: kBlocks * cols), eliminated and substituted forward
/// in one sweep, substituted back, and transposed out. Each lane computes exactly the scalar
/// Thomas algorithm of its row. The elimination is a chain of divisions along the row: its latency
/// is the cost, so the values just computed stay in registers and two blocks' chains interleave.
template <int kPlanes, int kBlocks>
void horizontalBlocks(const Weights& w, float* const* planes, int rows, int cols, float lambda,
                      int b, Lanes* x, Lanes* ratio_scratch) {
  Lanes* row[kBlocks][kPlanes];
  Lanes* ratio[kBlocks];
  const Lanes* weight[kBlocks];
  int row_count[kBlocks];
  for (int j = 0; j < kBlocks; ++j) {
    const int r0 = (b + j) * kLaneCount;
    row_count[j] = std::min(kLaneCount, rows - r0);
    for (int p = 0; p < kPlanes; ++p) {
      row[j][p] = x + std::size_t(j * kPlanes + p) * cols;
      rowsToLanes(planes[p] + std::size_t(r0) * cols, cols, row_count[j], cols, row[j][p]);
    }
    ratio[j] = ratio_scratch + std::size_t(j) * cols;
    weight[j] = w.horizontalLanes() + std::size_t(b + j) * cols;
  }
  Lanes previous[kBlocks], last_ratio[kBlocks], last[kBlocks][kPlanes];
  for (int j = 0; j < kBlocks; ++j) {
    previous[j] = lambda * weight[j][0];
    const Lanes inverse = 1.0f / (1.0f - previous[j]);
    ratio[j][0] = last_ratio[j] = previous[j] * inverse;
    for (int p = 0; p < kPlanes; ++p)
      row[j][p][0] = last[j][p] = row[j][p][0] * inverse;
  }
  for (int c = 1; c < cols; ++c) {
    for (int j = 0; j < kBlocks; ++j) {
      const Lanes current = lambda * weight[j][c];
      const Lanes inverse = 1.0f / ((1.0f - previous[j] - current) - last_ratio[j] * previous[j]);
      ratio[j][c] = last_ratio[j] = current * inverse;
      for (int p = 0; p < kPlanes; ++p)
        row[j][p][c] = last[j][p] = (row[j][p][c] - last[j][p] * previous[j]) * inverse;
      previous[j] = current;
    }
  }
  for (int c = cols - 2; c >= 0; --c) {
    for (int j = 0; j < kBlocks; ++j) {
      const Lanes q = ratio[j][c];
      for (int p = 0; p < kPlanes; ++p)
        row[j][p][c] = last[j][p] = row[j][p][c] - q * last[j][p];
    }
  }
  for (int j = 0; j < kBlocks; ++j) {
    const int r0 = (b + j) * kLaneCount;
    for (int p = 0; p < kPlanes; ++p)
      lanesToRows(row[j][p], row_count[j], cols, planes[p] + std::size_t(r0) * cols, cols);
  }
}

constexpr int kBlocksPerTask = 2;
using HorizontalBlocksFunction = void (*)(const Weights&, float* const*, int, int, float, int,
                                          Lanes*, Lanes*);
/// [plane count - 1][block count - 1]
constexpr HorizontalBlocksFunction kHorizontalBlocks[kMaxPlanes][kBlocksPerTask] = {
    {horizontalBlocks<1, 1>, horizontalBlocks<1, 2>},
    {horizontalBlocks<2, 1>, horizontalBlocks<2, 2>},
    {horizontalBlocks<3, 1>, horizontalBlocks<3, 2>},
    {horizontalBlocks<4, 1>, horizontalBlocks<4, 2>}};

/// Asks for the cache lines of `count` floats from `p` ahead of use: the vertical sweeps step a
/// whole image row (several kB, a new page) per row, which the hardware prefetchers do not follow.
inline void prefetchSpan(const float* p, int count) {
  for (int i = 0; i < count; i += 16)
    __builtin_prefetch(p + i);
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
    if (r + kPrefetchRows < rows) {
      prefetchSpan(w.vertical.ptr<float>(r + kPrefetchRows) + c0, width);
      for (int p = 0; p < plane_count; ++p)
        prefetchSpan(planes[p] + std::size_t(r + kPrefetchRows) * cols + c0, width);
    }
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
    if (r >= kPrefetchRows) {
      for (int p = 0; p < plane_count; ++p)
        prefetchSpan(planes[p] + std::size_t(r - kPrefetchRows) * cols + c0, width);
    }
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
  const Weights weights =
      edgeWeights(guide, static_cast<float>(params.sigma_color), params.vertical_edges, pool);
  float* data[kMaxPlanes];
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (!planes[p].isContinuous()) planes[p] = planes[p].clone();
    data[p] = planes[p].ptr<float>(0);
  }
  const int plane_count = static_cast<int>(planes.size());
  // Per-worker scratch (small enough to stay in cache): a lane block's planes and ratios, a column
  // chunk's ratios.
  std::vector<SimdVector<float>> lane_scratch(pool.size());
  for (SimdVector<float>& s : lane_scratch)
    s.resize(std::size_t(cols) * (plane_count + 1) * kBlocksPerTask * kLaneCount);
  std::vector<std::vector<float>> scratch(pool.size());
  for (std::vector<float>& s : scratch)
    s.resize(std::size_t(rows) * std::min(cols, kColumnChunk));
  const int row_blocks = (rows + kLaneCount - 1) / kLaneCount;
  const int row_tasks = (row_blocks + kBlocksPerTask - 1) / kBlocksPerTask;
  const int column_chunks = (cols + kColumnChunk - 1) / kColumnChunk;
  float lambda = static_cast<float>(params.lambda);
  for (int iteration = 0; iteration < params.iterations; ++iteration) {
    pool.parallelFor(row_tasks, [&](long long task, int worker) {
      const int b = static_cast<int>(task) * kBlocksPerTask;
      const int blocks = std::min(kBlocksPerTask, row_blocks - b);
      Lanes* x = reinterpret_cast<Lanes*>(lane_scratch[worker].data());
      kHorizontalBlocks[plane_count - 1][blocks - 1](
          weights, data, rows, cols, lambda, b, x,
          x + std::size_t(kBlocksPerTask) * plane_count * cols);
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
