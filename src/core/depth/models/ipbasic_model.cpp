#include "multimodal_nvs/core/depth/models/ipbasic_model.hpp"

// `ipbasic` baseline: classical morphological depth completion after Ku et al. 2018 (fast variant),
// on the sparse depth image of the samples projected onto the stride grid. Steps and the kernel
// scaling are documented in baselines.hpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "multimodal_nvs/core/common/bilateral_filter.hpp"
#include "multimodal_nvs/core/common/distance_transform.hpp"
#include "multimodal_nvs/core/common/rect_morphology.hpp"
#include "multimodal_nvs/core/common/sparse_dilation.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/striped_filters.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/models/distance_variance.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {
namespace {

constexpr float kEmpty = 0.1f;  // inverted values at or below this are holes

/// Odd kernel size for a published size `published` scaled by `scale` (at least 3).
int scaledSize(int published, double scale) {
  const int size = static_cast<int>(std::lround(published * scale));
  return std::max(3, size | 1);
}

/// Kernel size from which rectDilate's O(log k) doubling beats OpenCV's O(k) row and column
/// filters on stripes. Measured on a 1936x1216 float image at 2 threads, two runs, ms:
/// k = 13: 1.7 / 1.8 (OpenCV) against 2.2 / 2.7 (doubling); k = 33: 3.1 / 2.9 against 3.3 / 3.0;
/// k = 41: 3.9 / 3.6 against 3.9 / 2.7; k = 75: 6.6 / 10.6 against 2.7 / 4.7. Same bits.
constexpr int kDoublingMinKernel = 41;

cv::Mat rect(int size) {
  return cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size));
}

/// Empty pixels of `image` take the value of a full-kernel dilation (`dilated`, `empty`: scratch).
/// Only the bounding box of the empty pixels is dilated: like cv::dilate, rectDilate reads the
/// neighbours outside a ROI from the parent image, so the values there are those of the full-image
/// dilation (outputs unchanged), and after the earlier fills the box is often a fraction of the
/// image.
/// Rows outside [data_top, data_bottom] hold no value (they are 0): a dilation reaches at most
/// size / 2 rows beyond them, so the box is clipped there (outside, the dilation is 0, the value
/// the empty pixels already have).
void fillFromDilation(cv::Mat& image, int size, int data_top, int data_bottom,
                      std::vector<float>& dilated_storage, cv::Mat& empty, ThreadPool& pool) {
  cv::compare(image, kEmpty, empty, cv::CMP_LE);
  cv::Rect box = cv::boundingRect(empty);
  const int top = std::max(box.y, data_top - size / 2);
  const int bottom = std::min(box.y + box.height, data_bottom + size / 2 + 1);
  box.y = top;
  box.height = std::max(0, bottom - top);
  if (box.empty()) return;
  cv::Mat roi = image(box);
  // The box's size changes from call to call: a header over a buffer that never shrinks avoids
  // a fresh allocation (and its page faults) per call.
  dilated_storage.resize(std::max(dilated_storage.size(), std::size_t(box.area())));
  cv::Mat dilated(box.height, box.width, CV_32FC1, dilated_storage.data());
  if (size >= kDoublingMinKernel) {
    rectDilate(roi, dilated, size, pool);
  } else {
    stripedDilate(roi, dilated, rect(size), pool);
  }
  dilated.copyTo(roi, empty(box));
}

/// Full-image scratch images, kept per thread across frames. Why: a fresh full-resolution float
/// image costs a first-touch page fault per 4 KiB; on the measured 2-core VM that was ~75 ms per
/// 1936x1216 image (~30 us per fault, `perf stat -e page-faults`: 13.8k faults per frame before),
/// more than the morphology itself. cv::Mat::create keeps the memory when the size is unchanged.
struct IpBasicScratch {
  cv::Mat median, smooth;
  std::vector<float> dilated;  // of the hole fills
  cv::Mat mask;
  cv::Mat vertical;  // of the distance transform
  std::vector<long long> pixel_of_sample;
};

/// Extends each column's topmost value (above kEmpty) to the top row. Row by row, so that the
/// image is read in memory order: `top[c]` is column c's value once it has been seen.
void extendTopValues(cv::Mat& image) {
  const int rows = image.rows, cols = image.cols;
  std::vector<float> top(cols, 0.0f);
  std::vector<int> first_row(cols, -1);
  int unseen = cols;
  for (int r = 0; r < rows && unseen > 0; ++r) {
    const float* row = image.ptr<float>(r);
    for (int c = 0; c < cols; ++c) {
      if (first_row[c] < 0 && row[c] > kEmpty) {
        first_row[c] = r;
        top[c] = row[c];
        --unseen;
      }
    }
  }
  for (int r = 0; r < rows; ++r) {
    float* row = image.ptr<float>(r);
    bool above_any = false;
    for (int c = 0; c < cols; ++c) {
      if (r < first_row[c]) {
        row[c] = top[c];
        above_any = true;
      }
    }
    if (!above_any) break;
  }
}

}  // namespace

void predictIpBasic(const std::vector<AngularSample>& all_samples, const PixelAngleGrid& angles,
                    const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out) {
  const StrideGrid& grid = angles.grid();
  const int rows = grid.rows(), cols = grid.cols();
  const std::vector<AngularSample> samples = usableSamples(all_samples);
  if (samples.empty()) {
    setNoPrediction(grid, out);
    return;
  }
  const PinholeIntrinsics& k = angles.intrinsics();
  const std::size_t pixels = static_cast<std::size_t>(grid.size());
  out.mean.resize(pixels);
  out.variance.resize(pixels);
  // The output buffers double as the working image (mean) and the distance image (variance); the
  // last pass turns them into the prediction pixel by pixel.
  cv::Mat work(rows, cols, CV_32FC1, out.mean.data());
  cv::Mat distance(rows, cols, CV_32FC1, out.variance.data());
  thread_local IpBasicScratch scratch;

  // Sparse inverted depth on the grid: nearest return per pixel = the largest inverted value. The
  // projections (tan, cos per sample; ~80 k samples of a 64-beam scan) run on the pool, the
  // scatter stays serial so that its order, and the result, do not depend on the thread count.
  float max_depth = 0.0f;
  for (const AngularSample& s : samples)
    max_depth = std::max(max_depth, s.depth);
  const float offset = max_depth + 1.0f;
  // Row-major grid index per sample, -1: not on the grid. A reference, so that the pool's workers
  // write this thread's buffer and not their own thread_local one.
  std::vector<long long>& pixel_of_sample = scratch.pixel_of_sample;
  pixel_of_sample.resize(samples.size());
  constexpr long long kSamplesPerTask = 8192;
  const long long tasks =
      (static_cast<long long>(samples.size()) + kSamplesPerTask - 1) / kSamplesPerTask;
  pool.parallelFor(tasks, [&](long long task, int) {
    const std::size_t end = std::min(samples.size(), std::size_t((task + 1) * kSamplesPerTask));
    for (std::size_t i = std::size_t(task * kSamplesPerTask); i < end; ++i) {
      double u = 0, v = 0;
      pixel_of_sample[i] = -1;
      if (!angularToPixel(k, samples[i].azimuth_deg, samples[i].elevation_deg, &u, &v)) continue;
      const long c = std::lround(u / grid.stride), r = std::lround(v / grid.stride);
      if (c < 0 || r < 0 || c >= cols || r >= rows) continue;
      pixel_of_sample[i] = static_cast<long long>(r) * cols + c;
    }
  });
  work.setTo(cv::Scalar(0));
  float* sparse = work.ptr<float>(0);  // continuous: it wraps the output buffer
  int row_min = rows, row_max = -1;
  long long occupied = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const long long index = pixel_of_sample[i];
    if (index < 0) continue;
    float& pixel = sparse[index];
    const float inverted = offset - samples[i].depth;
    if (pixel == 0.0f) ++occupied;
    pixel = std::max(pixel, inverted);
    row_min = std::min(row_min, static_cast<int>(index / cols));
    row_max = std::max(row_max, static_cast<int>(index / cols));
  }
  if (occupied == 0) {
    setNoPrediction(grid, out);
    return;
  }

  // Distance of every pixel to the nearest projected sample (grid pixels), for the variance.
  cv::compare(work, kEmpty, scratch.mask, cv::CMP_LE);
  exactDistanceTransform(scratch.mask, distance, scratch.vertical, pool);

  // Kernel scale from the spacing of the projected returns.
  const double area = double(row_max - row_min + 1) * cols;
  const double spacing = std::sqrt(area / double(occupied));
  const double scale = std::min(8.0, std::max(0.5, spacing / kIpBasicReferenceSpacing));

  // Diamond (L1 ball) of odd size n, written around each projected return (the image is sparse
  // and non-negative: the same bits as n / 2 passes of the 3x3 cross over every pixel). Then the
  // closing, in cache-sized stripes.
  dilateSparseByDiamond(work, pixel_of_sample, scaledSize(5, scale) / 2, scratch.median, pool);
  stripedMorphology(scratch.median, work, cv::MORPH_CLOSE, rect(scaledSize(5, scale)), 1, pool);
  // Rows that can hold a value after the diamond and the closing: within their reach of the
  // projected returns' rows.
  const int reach = scaledSize(5, scale) / 2 + scaledSize(5, scale) / 2;
  fillFromDilation(work, scaledSize(7, scale), row_min - reach, row_max + reach, scratch.dilated,
                   scratch.mask, pool);
  extendTopValues(work);
  fillFromDilation(work, scaledSize(31, scale), 0, rows - 1, scratch.dilated, scratch.mask, pool);
  stripedMedianBlur(work, scratch.median, 5, pool);
  bilateralFilterFloat(scratch.median, scratch.smooth, 5, 1.5, 2.0, pool);

  // Smoothing must not erase a fill at a hole's border: keep the unsmoothed value there.
  const double deg_per_pixel = grid.stride * 180.0 / (3.14159265358979323846 * k.fx);
  const float no_mean = std::numeric_limits<float>::quiet_NaN();
  constexpr int kRowBlock = 16;
  const cv::Mat& smoothed = scratch.smooth;
  pool.parallelFor((rows + kRowBlock - 1) / kRowBlock, [&](long long block, int) {
    const int r0 = static_cast<int>(block) * kRowBlock;
    for (int r = r0; r < std::min(rows, r0 + kRowBlock); ++r) {
      float* mean = work.ptr<float>(r);     // the filled image before smoothing, then the mean
      float* var = distance.ptr<float>(r);  // the distance, then the variance
      const float* smooth = smoothed.ptr<float>(r);
      // Branch-free, with every value it reads kept in locals (a captured float might alias the
      // stores), so that the loop vectorises; this file is built with -fno-trapping-math.
      const float inversion = offset, missing = no_mean;
      const double scale_deg = deg_per_pixel;
      for (int c = 0; c < cols; ++c) {
        const float filled = mean[c], smoothed_value = smooth[c];
        const bool lost = (smoothed_value <= kEmpty) & (filled > kEmpty);
        const float value = lost ? filled : smoothed_value;
        const bool predicted = value > kEmpty;
        const float variance = static_cast<float>(distanceVariance(var[c] * scale_deg, params));
        mean[c] = predicted ? inversion - value : missing;
        var[c] = predicted ? variance : kNoPrediction;
      }
    }
  });
}

}  // namespace multimodal_nvs
