#include "multimodal_nvs/core/common/rect_morphology.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace {

// Columns per task of the column pass: its padded band (rows + kernel) x 128 floats stays in L2.
constexpr int kBandColumns = 128;
constexpr int kRowBlock = 16;  // rows per task of the row pass

struct Maximum {
  static constexpr float kOutside = -std::numeric_limits<float>::infinity();
  static float pick(float a, float b) { return std::max(a, b); }
};

struct Minimum {
  static constexpr float kOutside = std::numeric_limits<float>::infinity();
  static float pick(float a, float b) { return std::min(a, b); }
};

/// Turns rows [0, count) of `lines` (each `width` floats, `stride` apart; the rows past the
/// content are padding of Op::kOutside) into extrema of `span` consecutive lines, span the largest
/// power of two <= ksize, and returns span. In place, ascending: line i + s is read before it is
/// overwritten. The last lines' windows run past the end, where the padding does not change them.
template <typename Op>
int doubleSpans(float* lines, int count, int width, std::size_t stride, int ksize) {
  int span = 1;
  for (; 2 * span <= ksize; span *= 2) {
    for (int i = 0; i + span < count; ++i) {
      float* __restrict target = lines + i * stride;
      const float* __restrict further = lines + (i + span) * stride;
      for (int c = 0; c < width; ++c)
        target[c] = Op::pick(target[c], further[c]);
    }
  }
  return span;
}

/// doubleSpans for the pixels of one row: values[i] becomes the extremum of values[i, i + span).
/// In place, ascending (value i + s is read before it is overwritten), which vectorises.
template <typename Op>
int doubleSpansInRow(float* values, int count, int ksize) {
  int span = 1;
  for (; 2 * span <= ksize; span *= 2) {
    for (int i = 0; i + span < count; ++i)
      values[i] = Op::pick(values[i], values[i + span]);
  }
  return span;
}

template <typename Op>
void slidingExtremum(const cv::Mat& in, cv::Mat& out, int ksize, ThreadPool& pool) {
  if (in.type() != CV_32FC1) throw InputError("rect morphology: image must be CV_32FC1");
  if (ksize < 1 || ksize % 2 == 0) throw InputError("rect morphology: kernel size must be odd");
  const int h = ksize / 2, rows = in.rows, cols = in.cols;
  if (rows == 0 || cols == 0) {
    out.create(rows, cols, CV_32FC1);
    return;
  }
  // The context OpenCV reads: up to h pixels of the parent around a ROI.
  cv::Size whole;
  cv::Point offset;
  in.locateROI(whole, offset);
  const int top = std::min(h, offset.y), bottom = std::min(h, whole.height - offset.y - rows);
  const int left = std::min(h, offset.x), right = std::min(h, whole.width - offset.x - cols);
  cv::Mat context = in;  // a header: adjustROI widens the view, not the data
  context.adjustROI(top, bottom, left, right);
  const int context_rows = context.rows, context_cols = context.cols;

  // Column pass: vertical[r][c] = extremum of context column c over the window of output row r.
  // Kept across calls in a vector that never shrinks: the calls come with different ROI sizes,
  // and a fresh buffer costs a page fault per 4 KiB on first touch. A header over it, so that
  // the workers write this thread's buffer.
  thread_local std::vector<float> vertical_storage;
  vertical_storage.resize(std::max(vertical_storage.size(), std::size_t(rows) * context_cols));
  cv::Mat vertical(rows, context_cols, CV_32FC1, vertical_storage.data());
  const int bands = (context_cols + kBandColumns - 1) / kBandColumns;
  pool.parallelFor(bands, [&](long long b, int) {
    const int c0 = static_cast<int>(b) * kBandColumns;
    const int width = std::min(context_cols, c0 + kBandColumns) - c0;
    const int count = context_rows + 2 * h;  // h padding lines above and below
    thread_local std::vector<float> band;
    band.resize(std::size_t(count) * kBandColumns);
    for (int i = 0; i < count; ++i) {
      float* line = band.data() + std::size_t(i) * kBandColumns;
      const int r = i - h;
      if (r < 0 || r >= context_rows) {
        std::fill(line, line + width, Op::kOutside);
      } else {
        std::copy_n(context.ptr<float>(r) + c0, width, line);
      }
    }
    const int span = doubleSpans<Op>(band.data(), count, width, kBandColumns, ksize);
    // Output row r is context row r + top; its window starts at padded line r + top.
    for (int r = 0; r < rows; ++r) {
      const float* __restrict first = band.data() + std::size_t(r + top) * kBandColumns;
      const float* __restrict second = first + std::size_t(ksize - span) * kBandColumns;
      float* __restrict target = vertical.ptr<float>(r) + c0;
      for (int c = 0; c < width; ++c)
        target[c] = Op::pick(first[c], second[c]);
    }
  });

  // Row pass: the same along each row of `vertical`.
  out.create(rows, cols, CV_32FC1);
  const int blocks = (rows + kRowBlock - 1) / kRowBlock;
  pool.parallelFor(blocks, [&](long long b, int) {
    thread_local std::vector<float> line;
    const int count = context_cols + 2 * h;
    line.resize(count);
    const int r0 = static_cast<int>(b) * kRowBlock;
    for (int r = r0; r < std::min(rows, r0 + kRowBlock); ++r) {
      std::fill(line.begin(), line.begin() + h, Op::kOutside);
      std::copy_n(vertical.ptr<float>(r), context_cols, line.begin() + h);
      std::fill(line.begin() + h + context_cols, line.end(), Op::kOutside);
      const int span = doubleSpansInRow<Op>(line.data(), count, ksize);
      float* target = out.ptr<float>(r);
      const float* first = line.data() + left;  // output column c is context column c + left
      const float* second = first + (ksize - span);
      for (int c = 0; c < cols; ++c)
        target[c] = Op::pick(first[c], second[c]);
    }
  });
}

}  // namespace

void rectDilate(const cv::Mat& in, cv::Mat& out, int ksize, ThreadPool& pool) {
  slidingExtremum<Maximum>(in, out, ksize, pool);
}

void rectErode(const cv::Mat& in, cv::Mat& out, int ksize, ThreadPool& pool) {
  slidingExtremum<Minimum>(in, out, ksize, pool);
}

}  // namespace multimodal_nvs
