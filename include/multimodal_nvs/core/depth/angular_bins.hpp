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
    const auto [x0, x1] = binSpan(az - reach, az + reach, min_az_, nx_);
    const auto [y0, y1] = binSpan(el - reach, el + reach, min_el_, ny_);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::size_t b = std::size_t(y) * nx_ + x;
        for (int k = start_[b]; k < start_[b + 1]; ++k)
          visit(order_[k]);
      }
    }
  }

  /// Samples binned.
  std::size_t size() const { return order_.size(); }

  /// Calls visit(sample_index, azimuth, elevation) for every sample in the bins that intersect
  /// the disc of radius `reach` around (az, el), reading the angles in bin order (sequentially);
  /// each bin row is walked only across the disc's chord at the row's nearest elevation (a square
  /// walk visits 4/pi times the area). The caller applies the exact distance test.
  template <typename Visit>
  void queryDisc(double az, double el, double reach, Visit&& visit) const {
    forEachDiscRow(az, el, reach, [&](int begin, int end) {
      for (int k = begin; k < end; ++k)
        visit(order_[k], binned_az_[k], binned_el_[k]);
    });
  }

  /// The (at most) k samples nearest to (az, el), as (squared distance, index), nearest first
  /// (ties by index). `out` is cleared first. `start_reach` (degrees) is the first search radius:
  /// a neighbouring query's k-th distance makes one round enough.
  void nearest(double az, double el, int k, std::vector<std::pair<double, int>>& out,
               double start_reach = 0.0) const;

 private:
  std::size_t binOf(const AngularSample& s) const;
  /// One round of the bin walk over the disc of radius `reach`: the k smallest (distance, index)
  /// pairs among the samples at squared distance <= `bound`, nearest first, into `out`.
  void collect(double az, double el, double reach, std::size_t k, double bound,
               std::vector<std::pair<double, int>>& out) const;
  /// Calls row(begin, end) with the range of positions in order_ of each bin row's part that meets
  /// the disc of radius `reach` around (az, el): the row is walked only across the disc's chord at
  /// its nearest elevation to the centre.
  template <typename Row>
  void forEachDiscRow(double az, double el, double reach, Row&& row) const {
    if (order_.empty()) return;
    const auto [y0, y1] = binSpan(el - reach, el + reach, min_el_, ny_);
    for (int y = y0; y <= y1; ++y) {
      const double row_lo = min_el_ + y * bin_, row_hi = row_lo + bin_;
      const double dy = el < row_lo ? row_lo - el : (el > row_hi ? el - row_hi : 0.0);
      const double half = std::sqrt(std::max(0.0, reach * reach - dy * dy));
      const auto [x0, x1] = binSpan(az - half, az + half, min_az_, nx_);
      if (x0 > x1) continue;
      const std::size_t first = std::size_t(y) * nx_;
      row(start_[first + x0], start_[first + x1 + 1]);
    }
  }
  /// The bins [first, last] along one axis (bins of side bin_ from `origin`, `count` of them) that
  /// meet the interval [lo, hi]; first > last when none does.
  std::pair<int, int> binSpan(double lo, double hi, double origin, int count) const {
    return {std::max(0, static_cast<int>(std::floor((lo - origin) / bin_))),
            std::min(count - 1, static_cast<int>(std::floor((hi - origin) / bin_)))};
  }

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
