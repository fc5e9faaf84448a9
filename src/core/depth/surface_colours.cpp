#include "multimodal_nvs/core/depth/surface_colours.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "multimodal_nvs/core/depth/models/image_guided_model.hpp"

namespace multimodal_nvs {

SurfaceColours::SurfaceColours(const cv::Mat& image, const ImageSize& size, double sigma)
    // guideOnGrid checks and converts the image (8-bit BGR) as image_guided does; an 8-bit BGR
    // image is shared, not copied.
    : bgr_(guideOnGrid(image, StrideGrid{size, 1})),
      inv_two_sigma2_(sigma > 0.0 ? static_cast<float>(1.0 / (2.0 * sigma * sigma)) : 0.0f) {}

CellColour SurfaceColours::at(double u, double v) const {
  const double cu = std::floor(u / kCellPx), cv_ = std::floor(v / kCellPx);
  const int cols = bgr_.cols, rows = bgr_.rows;
  if (!(cu >= 0.0 && cv_ >= 0.0 && cu * kCellPx < cols && cv_ * kCellPx < rows)) {
    return {NAN, NAN, NAN};
  }
  // The cell's mean, computed where asked: the prior asks at its lattice nodes and returns only,
  // a few thousand cells, not the million of a whole averaged image.
  const int c0 = static_cast<int>(cu) * kCellPx, r0 = static_cast<int>(cv_) * kCellPx;
  const int c1 = std::min(cols, c0 + kCellPx), r1 = std::min(rows, r0 + kCellPx);
  int sum[3] = {0, 0, 0};
  for (int r = r0; r < r1; ++r) {
    const cv::Vec3b* row = bgr_.ptr<cv::Vec3b>(r);
    for (int c = c0; c < c1; ++c) {
      for (int ch = 0; ch < 3; ++ch)
        sum[ch] += row[c][ch];
    }
  }
  const float n = static_cast<float>((r1 - r0) * (c1 - c0));
  return {sum[0] / n, sum[1] / n, sum[2] / n};
}

CellColour SurfaceColours::atSample(const AngularSample& sample,
                                    const PixelAngleGrid& angles) const {
  double u = 0.0, v = 0.0;
  if (!angularToPixel(angles.intrinsics(), sample.azimuth_deg, sample.elevation_deg, &u, &v)) {
    return {NAN, NAN, NAN};
  }
  return at(u, v);
}

std::vector<CellColour> SurfaceColours::atSamples(const std::vector<AngularSample>& samples,
                                                  const PixelAngleGrid& angles) const {
  std::vector<CellColour> out(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
    out[i] = atSample(samples[i], angles);
  return out;
}

float SurfaceColours::weight(const CellColour& pixel, const CellColour& sample) const {
  if (std::isnan(pixel[0]) || std::isnan(sample[0])) return 1.0f;
  float d2 = 0.0f;
  for (int ch = 0; ch < 3; ++ch)
    d2 += (pixel[ch] - sample[ch]) * (pixel[ch] - sample[ch]);
  return kWeightFloor + (1.0f - kWeightFloor) * std::exp(-d2 * inv_two_sigma2_);
}

std::size_t weightedOrderStatistic(const std::vector<float>& depths,
                                   const std::vector<float>& weights, double fraction) {
  const std::size_t n = depths.size();
  // A handful of values (the prior's k nearest): an insertion sort of their indices by depth.
  std::array<std::size_t, 64> small{};
  std::vector<std::size_t> large;
  std::size_t* order = small.data();
  if (n > small.size()) {
    large.resize(n);
    order = large.data();
  }
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t j = i;
    for (; j > 0 && depths[order[j - 1]] > depths[i]; --j)
      order[j] = order[j - 1];
    order[j] = i;
  }
  const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  const double target = fraction * total;
  double cumulative = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    cumulative += weights[order[i]];
    if (cumulative >= target) return order[i];
  }
  return order[n - 1];
}

double wallDepth(double return_x, double return_depth, double pixel_x, double cap) {
  const bool between = return_x * pixel_x > 0.0 && std::abs(pixel_x) < std::abs(return_x);
  if (!between || std::abs(return_x) < kWallMinOffAxis) return return_depth;
  return std::min(return_x * return_depth / pixel_x, std::max(cap, return_depth));
}

}  // namespace multimodal_nvs
