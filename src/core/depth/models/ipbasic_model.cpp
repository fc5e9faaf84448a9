#include "multimodal_nvs/core/depth/models/ipbasic_model.hpp"

// `ipbasic` baseline: classical morphological depth completion after Ku et al. 2018 (fast variant),
// on the sparse depth image of the samples projected onto the stride grid. Steps and the kernel
// scaling are documented in baselines.hpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "multimodal_nvs/core/common/stride_grid.hpp"
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

/// Dilation with a diamond (L1 ball) of odd size `size`: radius iterations of the 3x3 cross, which
/// is exact for the L1 ball and costs O(radius) passes instead of O(size^2) per pixel.
void dilateDiamond(const cv::Mat& in, cv::Mat& out, int size) {
  const cv::Mat cross = cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(3, 3));
  cv::dilate(in, out, cross, cv::Point(-1, -1), size / 2);
}

cv::Mat rect(int size) {
  return cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size));
}

/// Empty pixels of `image` take the value of a full-kernel dilation.
void fillFromDilation(cv::Mat& image, int size) {
  cv::Mat dilated;
  cv::dilate(image, dilated, rect(size));
  const cv::Mat empty = image <= kEmpty;
  dilated.copyTo(image, empty);
}

}  // namespace

void predictIpBasic(const std::vector<AngularSample>& all_samples, const PixelAngleGrid& angles,
                    const DepthCompletionParams& params, ThreadPool& /*pool*/,
                    PixelPredictions& out) {
  const StrideGrid& grid = angles.grid();
  const int rows = grid.rows(), cols = grid.cols();
  setNoPrediction(grid, out);
  const std::vector<AngularSample> samples = usableSamples(all_samples);
  if (samples.empty()) return;
  const PinholeIntrinsics& k = angles.intrinsics();

  // Sparse inverted depth on the grid: nearest return per pixel = the largest inverted value.
  float max_depth = 0.0f;
  for (const AngularSample& s : samples)
    max_depth = std::max(max_depth, s.depth);
  const float offset = max_depth + 1.0f;
  cv::Mat image(rows, cols, CV_32FC1, cv::Scalar(0));
  int row_min = rows, row_max = -1;
  long long occupied = 0;
  for (const AngularSample& s : samples) {
    double u = 0, v = 0;
    if (!angularToPixel(k, s.azimuth_deg, s.elevation_deg, &u, &v)) continue;
    const long c = std::lround(u / grid.stride), r = std::lround(v / grid.stride);
    if (c < 0 || r < 0 || c >= cols || r >= rows) continue;
    float& pixel = image.at<float>(static_cast<int>(r), static_cast<int>(c));
    const float inverted = offset - s.depth;
    if (pixel == 0.0f) ++occupied;
    pixel = std::max(pixel, inverted);
    row_min = std::min(row_min, static_cast<int>(r));
    row_max = std::max(row_max, static_cast<int>(r));
  }
  if (occupied == 0) return;

  // Distance of every pixel to the nearest projected sample (grid pixels), for the variance.
  cv::Mat distance;
  cv::distanceTransform(image <= kEmpty, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);

  // Kernel scale from the spacing of the projected returns.
  const double area = double(row_max - row_min + 1) * cols;
  const double spacing = std::sqrt(area / double(occupied));
  const double scale = std::min(8.0, std::max(0.5, spacing / kIpBasicReferenceSpacing));

  cv::Mat work;
  dilateDiamond(image, work, scaledSize(5, scale));
  cv::morphologyEx(work, work, cv::MORPH_CLOSE, rect(scaledSize(5, scale)));
  fillFromDilation(work, scaledSize(7, scale));
  // Extend each column's topmost value to the top row.
  for (int c = 0; c < cols; ++c) {
    int top = 0;
    while (top < rows && work.at<float>(top, c) <= kEmpty)
      ++top;
    if (top == rows) continue;
    const float value = work.at<float>(top, c);
    for (int r = 0; r < top; ++r)
      work.at<float>(r, c) = value;
  }
  fillFromDilation(work, scaledSize(31, scale));
  const cv::Mat filled = work > kEmpty;
  cv::Mat median, smooth;
  cv::medianBlur(work, median, 5);
  cv::bilateralFilter(median, smooth, 5, 1.5, 2.0);
  // Smoothing must not erase a fill at a hole's border: keep the unsmoothed value there.
  const cv::Mat lost = (smooth <= kEmpty) & filled;
  work.copyTo(smooth, lost);

  const double deg_per_pixel = grid.stride * 180.0 / (3.14159265358979323846 * k.fx);
  for (int r = 0; r < rows; ++r) {
    const float* value = smooth.ptr<float>(r);
    const float* dist = distance.ptr<float>(r);
    const std::size_t row = std::size_t(r) * cols;
    for (int c = 0; c < cols; ++c) {
      if (!(value[c] > kEmpty)) continue;
      out.mean[row + c] = offset - value[c];
      out.variance[row + c] = static_cast<float>(distanceVariance(dist[c] * deg_per_pixel, params));
    }
  }
}

}  // namespace multimodal_nvs
