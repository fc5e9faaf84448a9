#pragma once
// Uniform bins over the angular domain, for radius and k-nearest queries among the samples.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/depth/angular_samples.hpp"

namespace multimodal_nvs {

/// Uniform square bins over the samples' angular bounding box, for radius and k-nearest queries
/// in the (azimuth, elevation) plane (degrees).
class AngularBins {
 public:
  AngularBins(const std::vector<AngularSample>& samples, double bin_deg);

  /// Calls visit(sample_index) for every sample in the bins that intersect the square of half
  /// side `reach` around (az, el); the caller applies the exact distance test.
  template <typename Visit>
  void query(double az, double el, double reach, Visit&& visit) const {
    if (order_.empty()) return;
    const int x0 = std::max(0, static_cast<int>(std::floor((az - reach - min_az_) / bin_)));
    const int x1 = std::min(nx_ - 1, static_cast<int>(std::floor((az + reach - min_az_) / bin_)));
    const int y0 = std::max(0, static_cast<int>(std::floor((el - reach - min_el_) / bin_)));
    const int y1 = std::min(ny_ - 1, static_cast<int>(std::floor((el + reach - min_el_) / bin_)));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::size_t b = std::size_t(y) * nx_ + x;
        for (int k = start_[b]; k < start_[b + 1]; ++k)
          visit(order_[k]);
      }
    }
  }

  /// The (at most) k samples nearest to (az, el), as (squared distance, index), nearest first
  /// (ties by index). `out` is cleared first. `start_reach` (degrees) is where
  /// the search square starts: a neighbouring query's k-th distance makes one round enough.
  void nearest(double az, double el, int k, std::vector<std::pair<double, int>>& out,
               double start_reach = 0.0) const;

 private:
  std::size_t binOf(const AngularSample& s) const;

  double bin_;
  double min_az_ = 0, max_az_ = 0, min_el_ = 0, max_el_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<int> start_;
  std::vector<int> order_;
  // The samples' angles in bin order (order_): nearest() reads them sequentially instead of
  // gathering AngularSample records from all over the scan (a 360-degree LiDAR sweep is megabytes).
  std::vector<float> binned_az_, binned_el_;
};

}  // namespace multimodal_nvs
