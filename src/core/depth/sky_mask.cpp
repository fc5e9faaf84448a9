#include "multimodal_nvs/core/depth/sky_mask.hpp"

// Hand-written passes (not cv::Sobel on the whole sky region and a walk down each column): at VoD
// full resolution that spelling took ~4.6 ms of the radar default's ~43 ms, serial: two float
// gradient images of the upper half written and read back column by column, a scan of the prior
// column by column, one hypotf call per sky pixel. Here every pass runs in bands of rows or strips
// of columns, row by row; the walk's tests are integer comparisons on a row of the strip at a time
// (they vectorise), and the gradient's square decides unless it is within rounding of the limit.
// The values are OpenCV's exactly: the Sobel sums of 8-bit pixels are integers, and OpenCV's float
// result (kernel scaled by 1/8) is that integer over 8 with no rounding anywhere (every partial
// sum needs < 24 bits).
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace multimodal_nvs {
namespace {

// Columns per task of the walk, rows per task of the other passes.
constexpr int kStripColumns = 256;
constexpr int kBandRows = 32;
constexpr int kNoRow = std::numeric_limits<int>::max();

/// OpenCV's default border (BORDER_REFLECT_101) for an index one step outside [0, length).
inline int reflect101(int i, int length) {
  if (length == 1) return 0;
  if (i < 0) return -i;
  if (i >= length) return 2 * length - i - 2;
  return i;
}

/// first[c] = r where the prior's row r is nearer than `far`, if r is before first[c]; returns
/// whether every column has its row now. Branch-free so that it vectorises.
bool firstNearerRow(const float* __restrict row, int cols, int r, float far,
                    int* __restrict first) {
  int latest = 0;
  for (int c = 0; c < cols; ++c) {
    const int hit = row[c] < far ? r : kNoRow;
    first[c] = first[c] < hit ? first[c] : hit;
    latest = latest > first[c] ? latest : first[c];
  }
  return latest != kNoRow;
}

/// The 3x3 Sobel sums (OpenCV's kernels, before its 1/8 scale) at column c of the gray row `here`;
/// `left` and `right` are the neighbouring columns (reflected at the image's border).
struct SobelSums {
  int x, y;
};
inline SobelSums sobelSums(const std::uint8_t* above, const std::uint8_t* here,
                           const std::uint8_t* below, int left, int c, int right) {
  return {
      (above[right] + 2 * here[right] + below[right]) -
          (above[left] + 2 * here[left] + below[left]),
      (below[left] + 2 * below[c] + below[right]) - (above[left] + 2 * above[c] + above[right])};
}

/// The per-pixel tests as integer thresholds on the 8-bit values, deciding as the double and float
/// comparisons do. The gradient test `hypot(x / 8, y / 8) > limit` on the Sobel sums x, y: the
/// integer x^2 + y^2 decides outside a margin around 64 limit^2 far wider than hypotf's rounding
/// (a relative 1e-5 against its ~1e-7); inside it hypotf itself does (gradientExceeds).
struct SkyTests {
  int dark_below;   // gray < brightness  <=>  gray < dark_below
  int warm_above;   // red - blue > max_warmth  <=>  red - blue > warm_above
  int steep_above;  // x^2 + y^2 > steep_above: surely an edge
  int flat_below;   // x^2 + y^2 < flat_below: surely none; in between, gradientExceeds decides
  float limit;

  SkyTests(double gradient, double brightness, double max_warmth) {
    dark_below = std::isnan(brightness) ? 0 : int(std::clamp(std::ceil(brightness), 0.0, 256.0));
    warm_above =
        std::isnan(max_warmth) ? 255 : int(std::clamp(std::floor(max_warmth), -256.0, 255.0));
    limit = static_cast<float>(gradient);
    const double limit_sq_64 = 64.0 * double(limit) * double(limit);
    const double margin = 1e-5 * limit_sq_64 + 1e-3;
    constexpr double kAboveAnySum = 1 << 22;  // x^2 + y^2 <= 2 * 1020^2
    if (std::isnan(limit_sq_64)) {            // hypot > NaN is false: never an edge
      steep_above = flat_below = int(kAboveAnySum);
    } else {
      steep_above = int(std::clamp(std::floor(limit_sq_64 + margin), -1.0, kAboveAnySum));
      flat_below = int(std::clamp(std::ceil(limit_sq_64 - margin), -1.0, kAboveAnySum));
    }
  }

  bool gradientExceeds(int x, int y) const {
    return std::hypot(static_cast<float>(x) * 0.125f, static_cast<float>(y) * 0.125f) > limit;
  }
};

/// One row of the walk's tests for columns [c0, c1) that are not on the image's border (c - 1 and
/// c + 1 exist): pass[c - c0] = the sky may go on through this pixel (1), or not (0), or the
/// gradient is too close to the limit to tell from the squares (2). Branch-free so that it
/// vectorises.
void skyTestsRow(const SkyTests& t, const std::uint8_t* __restrict above,
                 const std::uint8_t* __restrict here, const std::uint8_t* __restrict below,
                 const std::uint8_t* __restrict bgr, int c0, int c1,
                 std::uint8_t* __restrict pass) {
  const int dark_below = t.dark_below, warm_above = t.warm_above;
  const int steep_above = t.steep_above, flat_below = t.flat_below;
  for (int c = c0; c < c1; ++c) {
    const SobelSums g = sobelSums(above, here, below, c - 1, c, c + 1);
    const int sum = g.x * g.x + g.y * g.y;
    const bool other_end = (here[c] < dark_below) | (bgr[3 * c + 2] - bgr[3 * c] > warm_above);
    const bool steep = sum > steep_above, unsure = sum >= flat_below;
    pass[c - c0] = other_end | steep ? 0 : unsure ? 2 : 1;
  }
}

}  // namespace

std::vector<std::uint8_t> skyMask(const cv::Mat& guide, const std::vector<float>& prior,
                                  float far_depth, const std::vector<int>& top_return_row,
                                  double gradient, double brightness, double max_warmth,
                                  ThreadPool* pool) {
  if (prior.size() != guide.total())
    throw std::invalid_argument("skyMask: the prior is not of the guide's size");
  const std::size_t cols = static_cast<std::size_t>(guide.cols);
  return skyMask(
      guide,
      [&](int r, float* out) { std::copy_n(prior.data() + std::size_t(r) * cols, cols, out); },
      far_depth, top_return_row, gradient, brightness, max_warmth, pool);
}

std::vector<std::uint8_t> skyMask(const cv::Mat& guide, const PriorRowFunction& prior_row,
                                  float far_depth, const std::vector<int>& top_return_row,
                                  double gradient, double brightness, double max_warmth,
                                  ThreadPool* pool) {
  const int rows = guide.rows, cols = guide.cols;
  std::vector<std::uint8_t> sky(std::size_t(rows) * cols, 0);
  if (rows == 0 || cols == 0) return sky;
  // A column's sky ends at its top return and at its first pixel with a nearer prior (the ground):
  // each band of rows finds its first such row per column, the earliest band's wins. A band stops
  // at its first row where every column has one (below the horizon, its first row): the prior is
  // computed for the rows above the ground, not for the whole image.
  const int scan_rows =
      std::min(rows, *std::max_element(top_return_row.begin(), top_return_row.end()));
  const int bands = (scan_rows + kBandRows - 1) / kBandRows;
  std::vector<int> band_first(std::size_t(bands) * cols, kNoRow);
  std::vector<std::vector<float>> row_scratch(pool != nullptr ? pool->size() : 1,
                                              std::vector<float>(cols));
  parallelForOrInline(pool, bands, [&](long long band, int worker) {
    const int r0 = static_cast<int>(band) * kBandRows, r1 = std::min(scan_rows, r0 + kBandRows);
    float* row = row_scratch[worker].data();
    int* first = band_first.data() + std::size_t(band) * cols;
    for (int r = r0; r < r1; ++r) {
      prior_row(r, row);
      if (firstNearerRow(row, cols, r, far_depth, first)) break;
    }
  });
  std::vector<int> column_end(cols);
  for (int c = 0; c < cols; ++c) {
    column_end[c] = std::min(rows, top_return_row[c]);
    for (int b = 0; b < bands && column_end[c] > b * kBandRows; ++b)
      column_end[c] = std::min(column_end[c], band_first[std::size_t(b) * cols + c]);
  }
  const int end_rows = *std::max_element(column_end.begin(), column_end.end());
  if (end_rows == 0) return sky;
  // The gray image of the rows the walk reads: those above the lowest end and one more (the 3x3
  // gradient of the last row read needs the row below).
  const int gray_rows = std::min(rows, end_rows + 1);
  cv::Mat gray(gray_rows, cols, CV_8U);
  parallelForOrInline(pool, (gray_rows + kBandRows - 1) / kBandRows, [&](long long band, int) {
    const int r0 = static_cast<int>(band) * kBandRows;
    const int r1 = std::min(gray_rows, r0 + kBandRows);
    cv::Mat out = gray.rowRange(r0, r1);
    cv::cvtColor(guide.rowRange(r0, r1), out, cv::COLOR_BGR2GRAY);
  });
  const SkyTests tests(gradient, brightness, max_warmth);
  parallelForOrInline(pool, (cols + kStripColumns - 1) / kStripColumns, [&](long long strip, int) {
    const int c0 = static_cast<int>(strip) * kStripColumns;
    const int c1 = std::min(cols, c0 + kStripColumns);
    // The strip's columns off the image's border, where the tests vectorise.
    const int inner0 = std::max(c0, 1), inner1 = std::max(inner0, std::min(c1, cols - 1));
    std::uint8_t open[kStripColumns], pass[kStripColumns];
    int last = 0;
    for (int c = c0; c < c1; ++c) {
      open[c - c0] = column_end[c] > 0;
      last = std::max(last, column_end[c]);
    }
    for (int r = 0; r < last; ++r) {
      const std::uint8_t* above = gray.ptr<std::uint8_t>(reflect101(r - 1, gray_rows));
      const std::uint8_t* here = gray.ptr<std::uint8_t>(r);
      const std::uint8_t* below = gray.ptr<std::uint8_t>(reflect101(r + 1, gray_rows));
      const std::uint8_t* bgr = guide.ptr<std::uint8_t>(r);
      skyTestsRow(tests, above, here, below, bgr, inner0, inner1, pass + (inner0 - c0));
      bool any_open = false;
      std::uint8_t* sky_row = sky.data() + std::size_t(r) * cols;
      for (int c = c0; c < c1; ++c) {
        std::uint8_t& is_open = open[c - c0];
        if (!is_open) continue;
        bool goes_on;
        if (c >= inner0 && c < inner1 && pass[c - c0] != 2) {
          goes_on = pass[c - c0] == 1;
        } else {  // the image's border columns, or a gradient at the limit
          const SobelSums g =
              sobelSums(above, here, below, reflect101(c - 1, cols), c, reflect101(c + 1, cols));
          goes_on = here[c] >= tests.dark_below && !tests.gradientExceeds(g.x, g.y) &&
                    bgr[3 * c + 2] - bgr[3 * c] <= tests.warm_above;
        }
        // r < column_end[c] implies the prior is not nearer than far_depth (see above).
        is_open = goes_on && r < column_end[c];
        sky_row[c] = is_open;
        any_open |= is_open;
      }
      if (!any_open) break;
    }
  });
  return sky;
}

}  // namespace multimodal_nvs
