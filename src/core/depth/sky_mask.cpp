#include "multimodal_nvs/core/depth/sky_mask.hpp"

// Hand-written passes (not cv::Sobel on the whole sky region and a walk down each column): at VoD
// full resolution that spelling took ~4.6 ms of the radar default's ~43 ms, serial: two float
// gradient images of the upper half written and read back column by column, and one hypotf call
// per sky pixel. Here the columns are walked in strips, row by row, and the gradient is formed
// only at the pixels the walk reaches, from the gray image. The values are OpenCV's exactly: the
// Sobel sums of 8-bit pixels are integers, and OpenCV's float result (kernel scaled by 1/8) is
// that integer over 8 with no rounding anywhere (every partial sum needs < 24 bits).
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace multimodal_nvs {
namespace {

// Columns per task of the walks: a strip's row segment is a few cache lines of each input.
constexpr int kStripColumns = 64;
// Rows per task of the gray conversion.
constexpr int kGrayBandRows = 32;

/// OpenCV's default border (BORDER_REFLECT_101) for an index one step outside [0, length).
inline int reflect101(int i, int length) {
  if (length == 1) return 0;
  if (i < 0) return -i;
  if (i >= length) return 2 * length - i - 2;
  return i;
}

void forEachTask(ThreadPool* pool, long long count, const std::function<void(long long)>& body) {
  if (pool == nullptr) {
    for (long long i = 0; i < count; ++i)
      body(i);
    return;
  }
  pool->parallelFor(count, [&](long long i, int) { body(i); });
}

/// hypot(x / 8, y / 8) > limit for the Sobel sums x, y, as std::hypot on the floats decides it.
/// The squares decide wherever the two sides differ by more than hypotf's rounding (a relative
/// 1e-5 margin against its ~1e-7); in that margin hypotf itself does. Why: one hypotf call per sky
/// pixel was ~1.7 ms of a VoD frame.
inline bool gradientExceeds(int x, int y, float limit, double limit_sq_64, double margin) {
  const double sum = double(x) * x + double(y) * y;  // 64 x the squared gradient, exact
  if (sum > limit_sq_64 + margin) return true;
  if (sum < limit_sq_64 - margin) return false;
  return std::hypot(static_cast<float>(x) * 0.125f, static_cast<float>(y) * 0.125f) > limit;
}

}  // namespace

std::vector<std::uint8_t> skyMask(const cv::Mat& guide, const std::vector<float>& prior,
                                  float far_depth, const std::vector<int>& top_return_row,
                                  double gradient, double brightness, double max_warmth,
                                  ThreadPool* pool) {
  const int rows = guide.rows, cols = guide.cols;
  std::vector<std::uint8_t> sky(std::size_t(rows) * cols, 0);
  if (rows == 0 || cols == 0) return sky;
  const int strips = (cols + kStripColumns - 1) / kStripColumns;
  // A column's sky ends at its top return and at its first pixel with a nearer prior (the ground).
  std::vector<int> column_end(cols);
  forEachTask(pool, strips, [&](long long strip) {
    const int c0 = static_cast<int>(strip) * kStripColumns;
    const int c1 = std::min(cols, c0 + kStripColumns);
    int last = 0;
    for (int c = c0; c < c1; ++c) {
      column_end[c] = std::min(rows, top_return_row[c]);
      last = std::max(last, column_end[c]);
    }
    for (int r = 0; r < last; ++r) {  // row by row: the prior is row-major
      const float* prior_row = prior.data() + std::size_t(r) * cols;
      for (int c = c0; c < c1; ++c) {
        if (r < column_end[c] && prior_row[c] < far_depth) column_end[c] = r;
      }
    }
  });
  const int end_rows = *std::max_element(column_end.begin(), column_end.end());
  if (end_rows == 0) return sky;
  // The gray image of the rows the walk reads: those above the lowest end and one more (the 3x3
  // gradient of the last row read needs the row below).
  const int gray_rows = std::min(rows, end_rows + 1);
  cv::Mat gray(gray_rows, cols, CV_8U);
  forEachTask(pool, (gray_rows + kGrayBandRows - 1) / kGrayBandRows, [&](long long band) {
    const int r0 = static_cast<int>(band) * kGrayBandRows;
    const int r1 = std::min(gray_rows, r0 + kGrayBandRows);
    cv::Mat out = gray.rowRange(r0, r1);
    cv::cvtColor(guide.rowRange(r0, r1), out, cv::COLOR_BGR2GRAY);
  });
  const float limit = static_cast<float>(gradient);
  const double limit_sq_64 = 64.0 * double(limit) * double(limit);
  const double margin = 1e-5 * limit_sq_64 + 1e-9;
  forEachTask(pool, strips, [&](long long strip) {
    const int c0 = static_cast<int>(strip) * kStripColumns;
    const int c1 = std::min(cols, c0 + kStripColumns);
    std::uint8_t open[kStripColumns];
    int open_columns = 0, last = 0;
    for (int c = c0; c < c1; ++c) {
      open[c - c0] = column_end[c] > 0;
      open_columns += open[c - c0];
      last = std::max(last, column_end[c]);
    }
    for (int r = 0; r < last && open_columns > 0; ++r) {
      const std::uint8_t* above = gray.ptr<std::uint8_t>(reflect101(r - 1, gray_rows));
      const std::uint8_t* here = gray.ptr<std::uint8_t>(r);
      const std::uint8_t* below = gray.ptr<std::uint8_t>(reflect101(r + 1, gray_rows));
      const cv::Vec3b* bgr = guide.ptr<cv::Vec3b>(r);
      std::uint8_t* sky_row = sky.data() + std::size_t(r) * cols;
      for (int c = c0; c < c1; ++c) {
        std::uint8_t& is_open = open[c - c0];
        if (!is_open) continue;
        const int left = reflect101(c - 1, cols), right = reflect101(c + 1, cols);
        const int x = (above[right] + 2 * here[right] + below[right]) -
                      (above[left] + 2 * here[left] + below[left]);
        const int y = (below[left] + 2 * below[c] + below[right]) -
                      (above[left] + 2 * above[c] + above[right]);
        // r < column_end[c] implies the prior is not nearer than far_depth (see above).
        const bool ends = r >= column_end[c] || here[c] < brightness ||
                          gradientExceeds(x, y, limit, limit_sq_64, margin) ||
                          int(bgr[c][2]) - int(bgr[c][0]) > max_warmth;
        if (ends) {
          is_open = 0;
          --open_columns;
          continue;
        }
        sky_row[c] = 1;
      }
    }
  });
  return sky;
}

}  // namespace multimodal_nvs
