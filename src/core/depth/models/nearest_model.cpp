#include "multimodal_nvs/core/depth/models/nearest_model.hpp"

// `nearest` baseline: the depth of the angularly nearest sample — exact, with no radius limit.
// Samples go into a uniform bin grid in (azimuth, elevation). Pixels are handled in blocks: one
// expanding ring search finds the sample nearest to the block's centre (distance d_c); every pixel
// of the block (within h of the centre) then has its nearest sample within d_c + 2h of the centre,
// so a per-pixel scan of those few candidates is exact.
#include <algorithm>
#include <cmath>
#include <limits>

#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/models/distance_variance.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {
namespace {

/// Samples bucketed into square bins of side `bin` (degrees) covering a bounding box.
class AngularBins {
 public:
  AngularBins(const std::vector<AngularSample>& samples, float az0, float az1, float el0, float el1)
      : samples_(samples), az0_(az0), el0_(el0) {
    const double width = std::max(1e-3, double(az1) - az0);
    const double height = std::max(1e-3, double(el1) - el0);
    // About one sample per bin, but never more than ~4 bins per sample.
    const double n = static_cast<double>(std::max<std::size_t>(1, samples.size()));
    bin_ = static_cast<float>(std::max(std::sqrt(width * height / n), 1e-4));
    nx_ = static_cast<int>(std::ceil(width / bin_)) + 1;
    ny_ = static_cast<int>(std::ceil(height / bin_)) + 1;
    while (double(nx_) * ny_ > 4.0 * n + 64.0) {
      bin_ *= 1.5f;
      nx_ = static_cast<int>(std::ceil(width / bin_)) + 1;
      ny_ = static_cast<int>(std::ceil(height / bin_)) + 1;
    }
    start_.assign(std::size_t(nx_) * ny_ + 1, 0);
    for (const AngularSample& s : samples)
      ++start_[binOf(s.azimuth_deg, s.elevation_deg) + 1];
    for (std::size_t b = 1; b < start_.size(); ++b)
      start_[b] += start_[b - 1];
    members_.resize(samples.size());
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      members_[fill[binOf(samples[i].azimuth_deg, samples[i].elevation_deg)]++] = int(i);
    }
  }

  /// Appends every sample within `radius` of (az, el) to `out` (in no particular order).
  void within(float az, float el, float radius, std::vector<int>& out) const {
    const int x0 = clampX(az - radius), x1 = clampX(az + radius);
    const int y0 = clampY(el - radius), y1 = clampY(el + radius);
    const float r2 = radius * radius;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::size_t b = std::size_t(y) * nx_ + x;
        for (int m = start_[b]; m < start_[b + 1]; ++m) {
          const int i = members_[m];
          const float da = samples_[i].azimuth_deg - az, de = samples_[i].elevation_deg - el;
          if (da * da + de * de <= r2) out.push_back(i);
        }
      }
    }
  }

  /// Index of the nearest sample to (az, el) and its squared distance; ties: lower index.
  int nearest(float az, float el, float* best_d2) const {
    const int bx = clampX(az), by = clampY(el);
    int best = -1;
    float best_d = std::numeric_limits<float>::infinity();
    const int max_ring = std::max(nx_, ny_);
    for (int ring = 0; ring <= max_ring; ++ring) {
      const int x0 = bx - ring, x1 = bx + ring, y0 = by - ring, y1 = by + ring;
      for (int y = std::max(0, y0); y <= std::min(ny_ - 1, y1); ++y) {
        const bool edge_row = y == y0 || y == y1;
        const int step = edge_row ? 1 : std::max(1, x1 - x0);
        for (int x = x0; x <= x1; x += step) {
          if (x < 0 || x >= nx_) continue;
          const std::size_t b = std::size_t(y) * nx_ + x;
          for (int m = start_[b]; m < start_[b + 1]; ++m) {
            const int i = members_[m];
            const float da = samples_[i].azimuth_deg - az, de = samples_[i].elevation_deg - el;
            const float d2 = da * da + de * de;
            if (d2 < best_d || (d2 == best_d && i < best)) {
              best_d = d2;
              best = i;
            }
          }
        }
      }
      // Any sample in ring + 1 or beyond is at least ring * bin away along one axis.
      if (best >= 0) {
        const float reach = ring * bin_;
        if (best_d <= reach * reach) break;
      }
    }
    *best_d2 = best_d;
    return best;
  }

 private:
  int clampX(float az) const {
    return std::min(nx_ - 1, std::max(0, static_cast<int>(std::floor((az - az0_) / bin_))));
  }
  int clampY(float el) const {
    return std::min(ny_ - 1, std::max(0, static_cast<int>(std::floor((el - el0_) / bin_))));
  }
  std::size_t binOf(float az, float el) const { return std::size_t(clampY(el)) * nx_ + clampX(az); }

  const std::vector<AngularSample>& samples_;
  float az0_, el0_, bin_ = 1.0f;
  int nx_ = 1, ny_ = 1;
  std::vector<int> start_, members_;
};

}  // namespace

void predictNearest(const std::vector<AngularSample>& all_samples, const PixelAngleGrid& angles,
                    const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out) {
  const StrideGrid& grid = angles.grid();
  const int rows = grid.rows(), cols = grid.cols();
  setNoPrediction(grid, out);
  const std::vector<AngularSample> samples = usableSamples(all_samples);
  if (samples.empty()) return;

  // Bins over the union of the samples' and the pixels' angular bounding boxes: every pixel lies
  // inside the binned area, which the ring-search stopping rule relies on.
  const AngularBox box = boundingBox(samples), image = angles.extent();
  const AngularBins bins(samples, std::min(box.az_min, image.az_min),
                         std::max(box.az_max, image.az_max), std::min(box.el_min, image.el_min),
                         std::max(box.el_max, image.el_max));

  constexpr int kBlock = 8;
  const int block_rows = (rows + kBlock - 1) / kBlock, block_cols = (cols + kBlock - 1) / kBlock;
  std::vector<std::vector<int>> scratch(static_cast<std::size_t>(pool.size()));
  pool.parallelFor(
      static_cast<long long>(block_rows) * block_cols,
      [&](long long b, int worker) {
        const int r0 = static_cast<int>(b / block_cols) * kBlock;
        const int c0 = static_cast<int>(b % block_cols) * kBlock;
        const int r1 = std::min(rows, r0 + kBlock), c1 = std::min(cols, c0 + kBlock);
        float baz0 = std::numeric_limits<float>::infinity(), baz1 = -baz0, bel0 = baz0,
              bel1 = -baz0;
        for (int r = r0; r < r1; ++r) {
          const float* az = angles.azimuthRow(r);
          const float* el = angles.elevationRow(r);
          for (int c = c0; c < c1; ++c) {
            baz0 = std::min(baz0, az[c]);
            baz1 = std::max(baz1, az[c]);
            bel0 = std::min(bel0, el[c]);
            bel1 = std::max(bel1, el[c]);
          }
        }
        const float caz = 0.5f * (baz0 + baz1), cel = 0.5f * (bel0 + bel1);
        const float h = 0.5f * std::hypot(baz1 - baz0, bel1 - bel0);
        float dc2 = 0.0f;
        bins.nearest(caz, cel, &dc2);
        // Margin for float rounding of the distances involved.
        const float reach = std::sqrt(dc2) + 2.0f * h + 1e-3f;
        std::vector<int>& candidates = scratch[static_cast<std::size_t>(worker)];
        candidates.clear();
        bins.within(caz, cel, reach, candidates);
        std::sort(candidates.begin(), candidates.end());  // ties: the lower index wins
        for (int r = r0; r < r1; ++r) {
          const float* az = angles.azimuthRow(r);
          const float* el = angles.elevationRow(r);
          const std::size_t row = static_cast<std::size_t>(r) * cols;
          for (int c = c0; c < c1; ++c) {
            int best = candidates.front();
            float best_d = std::numeric_limits<float>::infinity();
            for (int i : candidates) {
              const float da = samples[i].azimuth_deg - az[c],
                          de = samples[i].elevation_deg - el[c];
              const float d2 = da * da + de * de;
              if (d2 < best_d) {
                best_d = d2;
                best = i;
              }
            }
            out.mean[row + c] = samples[best].depth;
            out.variance[row + c] =
                static_cast<float>(distanceVariance(std::sqrt(double(best_d)), params));
          }
        }
      },
      4);
}

}  // namespace multimodal_nvs
