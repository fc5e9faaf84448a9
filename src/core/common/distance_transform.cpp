#include "multimodal_nvs/core/common/distance_transform.hpp"

// Hand-written instead of cv::distanceTransform(DIST_MASK_PRECISE): OpenCV's took ~42 ms
// single-threaded on a 1936x1216 mask (the largest stage of the `ipbasic` baseline). Integer
// arithmetic makes the squared distance exact, so the float result is OpenCV's bit for bit
// (test_distance_transform compares them).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace {

constexpr int kColumnBand = 64;  // columns per task of the column sweeps (contiguous in memory)
constexpr int kRowBlock = 8;     // rows per task of the row pass

/// Column sweeps over columns [c0, c1): vertical[r][c] = rows to the nearest zero of column c, or
/// `far` when the column has none.
void columnSweeps(const cv::Mat& mask, cv::Mat& vertical, int c0, int c1, std::int32_t far) {
  const int rows = mask.rows;
  {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(0);
    std::int32_t* g = vertical.ptr<std::int32_t>(0);
    for (int c = c0; c < c1; ++c)
      g[c] = m[c] ? far : 0;
  }
  for (int r = 1; r < rows; ++r) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    const std::int32_t* above = vertical.ptr<std::int32_t>(r - 1);
    std::int32_t* g = vertical.ptr<std::int32_t>(r);
    for (int c = c0; c < c1; ++c)
      g[c] = m[c] ? std::min(far, above[c] + 1) : 0;
  }
  for (int r = rows - 2; r >= 0; --r) {
    const std::int32_t* below = vertical.ptr<std::int32_t>(r + 1);
    std::int32_t* g = vertical.ptr<std::int32_t>(r);
    for (int c = c0; c < c1; ++c)
      g[c] = std::min(g[c], below[c] + 1);
  }
}

/// Row pass (Meijster et al.'s second phase, squared Euclidean distance): the lower envelope of the
/// parabolas (x - i)^2 + g(i)^2. `Int` holds every squared distance and separator numerator
/// (int32 up to ~30k px of rows + cols, measured 2x faster than int64). `site`, `start`, `square`,
/// `squared` are scratch of the row's length; `half_reciprocal[k]` = 1 / (2k).
template <typename Int>
void rowPass(const std::int32_t* g, int cols, float* out, Int* site, Int* start, Int* square,
             Int* squared, const double* half_reciprocal) {
  for (int x = 0; x < cols; ++x)
    square[x] = Int(g[x]) * g[x];
  int q = 0;
  site[0] = 0;
  start[0] = 0;
  for (Int u = 1; u < cols; ++u) {
    const Int gu = square[u];
    while (q >= 0) {
      const Int t = start[q], i = site[q];
      if ((t - i) * (t - i) + square[i] <= (t - u) * (t - u) + gu) break;
      --q;
    }
    if (q < 0) {
      q = 0;
      site[0] = u;
      continue;
    }
    // First column where u lies below site[q]: it is not above u at start[q] >= 0, so the
    // numerator is >= 0 and `/` floors.
    const Int i = site[q];
    const Int numerator = u * u - i * i + gu - square[i];
    Int w;
    if constexpr (std::is_same<Int, std::int32_t>::value) {
      // floor(n / (2k)) as floor((n + 0.5) / (2k)) in double with a tabulated 1 / (2k): the
      // integer division was the latency of the envelope's dependency chain. Exact: the quotient
      // is then at least 0.5 / (2k) >= 1 / (4 cols) from an integer, while the double product of
      // a value below 2^31 errs by less than 2^31 * 2^-52 = 2^-21 (test_distance_transform
      // compares with OpenCV bit for bit).
      w = 1 + static_cast<Int>((numerator + 0.5) * half_reciprocal[u - i]);
    } else {
      w = 1 + numerator / (2 * (u - i));
    }
    if (w < cols) {
      ++q;
      site[q] = u;
      start[q] = w;
    }
  }
  // Squared distances first, then one vectorisable sqrt pass.
  for (Int x = cols - 1; x >= 0; --x) {
    const Int i = site[q];
    squared[x] = (x - i) * (x - i) + square[i];
    if (x == start[q]) --q;
  }
  for (int x = 0; x < cols; ++x)
    out[x] = std::sqrt(static_cast<float>(squared[x]));
}

template <typename Int>
void rowPasses(const cv::Mat& vertical, cv::Mat& distance, ThreadPool& pool) {
  const int rows = vertical.rows, cols = vertical.cols;
  const int blocks = (rows + kRowBlock - 1) / kRowBlock;
  std::vector<double> half_reciprocal(std::max(1, cols));
  for (int k = 1; k < cols; ++k)
    half_reciprocal[k] = 1.0 / (2.0 * k);
  pool.parallelFor(blocks, [&](long long b, int) {
    std::vector<Int> scratch(4 * std::size_t(cols));
    Int* site = scratch.data();
    const int r0 = static_cast<int>(b) * kRowBlock;
    for (int r = r0; r < std::min(rows, r0 + kRowBlock); ++r) {
      rowPass<Int>(vertical.ptr<std::int32_t>(r), cols, distance.ptr<float>(r), site, site + cols,
                   site + 2 * cols, site + 3 * cols, half_reciprocal.data());
    }
  });
}

}  // namespace

void exactDistanceTransform(const cv::Mat& mask, cv::Mat& distance, cv::Mat& vertical,
                            ThreadPool& pool) {
  if (mask.type() != CV_8UC1) throw InputError("exactDistanceTransform: mask must be CV_8UC1");
  const int rows = mask.rows, cols = mask.cols;
  distance.create(rows, cols, CV_32FC1);
  vertical.create(rows, cols, CV_32SC1);
  if (rows == 0 || cols == 0) return;
  // Larger than any distance inside the image.
  const std::int32_t far = rows + cols;
  const int bands = (cols + kColumnBand - 1) / kColumnBand;
  pool.parallelFor(bands, [&](long long b, int) {
    const int c0 = static_cast<int>(b) * kColumnBand;
    columnSweeps(mask, vertical, c0, std::min(cols, c0 + kColumnBand), far);
  });
  // Largest value the row pass forms: far^2 + cols^2 (a squared distance, a separator numerator).
  const long long largest = (long long)far * far + (long long)cols * cols;
  if (largest < (1LL << 30)) {
    rowPasses<std::int32_t>(vertical, distance, pool);
  } else {
    rowPasses<long long>(vertical, distance, pool);
  }
}

}  // namespace multimodal_nvs
