#include "multimodal_nvs/core/depth/region_nearest.hpp"

#include <algorithm>
#include <cmath>

namespace multimodal_nvs {
namespace {
/// The gather radius for a k-th distance bound and a region's extent, with slack for the rounding
/// of the distances (it only widens the gather).
double coveringRadius(double kth_bound, double extent) {
  return (kth_bound + 2.0 * extent) * (1.0 + 1e-6) + 1e-6;
}
}  // namespace

void RegionNearest::gather(const AngularBins& bins, double az, double el, double radius) {
  az_.clear();
  el_.clear();
  centre2_.clear();
  index_.clear();
  last_.clear();
  const double radius2 = radius * radius;
  bins.queryDisc(az, el, radius, [&](int i, float sample_az, float sample_el) {
    const double sa = sample_az, se = sample_el;
    const double da = sa - az, de = se - el;
    const double d2 = da * da + de * de;
    if (d2 > radius2) return;
    az_.push_back(sa);
    el_.push_back(se);
    centre2_.push_back(d2);
    index_.push_back(i);
  });
}

void RegionNearest::keepWithin(double radius2) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < index_.size(); ++i) {
    if (centre2_[i] > radius2) continue;
    az_[kept] = az_[i];
    el_[kept] = el_[i];
    centre2_[kept] = centre2_[i];
    index_[kept] = index_[i];
    ++kept;
  }
  az_.resize(kept);
  el_.resize(kept);
  centre2_.resize(kept);
  index_.resize(kept);
}

double RegionNearest::gatherAround(const AngularBins& bins, double az, double el, double extent,
                                   std::size_t k, double guess) {
  double bound = guess > 0.0 ? guess : 1.0;
  for (;;) {
    gather(bins, az, el, coveringRadius(bound, extent));
    // Every sample gathered: whatever k is, nothing is missing.
    if (index_.size() == bins.size()) break;
    const double bound2 = bound * bound;
    const std::size_t within = static_cast<std::size_t>(
        std::count_if(centre2_.begin(), centre2_.end(), [&](double d2) { return d2 <= bound2; }));
    if (k == 0 || within < k) {
      bound *= 2.0;
      continue;
    }
    // The centre's exact k-th distance: a guess that was too generous must not leave each query
    // scanning the surplus.
    thread_local std::vector<double> order;
    order.assign(centre2_.begin(), centre2_.end());
    std::nth_element(order.begin(), order.begin() + static_cast<long>(k - 1), order.end());
    bound = std::sqrt(order[k - 1]);
    const double radius = coveringRadius(bound, extent);
    keepWithin(radius * radius);
    break;
  }
  distance2_.resize(index_.size());
  passed_.resize(index_.size());
  return bound;
}

void RegionNearest::nearest(double az, double el, std::size_t k,
                            std::vector<std::pair<double, int>>& out) {
  out.clear();
  const std::size_t m = index_.size();
  if (k == 0 || m == 0) return;
  best_.resize(k);
  // The same expression as AngularBins' walk (the package builds without FMA contraction), so the
  // squared distances, and with them the order and the ties, are the same bits. A plain loop over
  // the region: it vectorises.
  const double* __restrict const sa = az_.data();
  const double* __restrict const se = el_.data();
  double* __restrict const d2 = distance2_.data();
  for (std::size_t i = 0; i < m; ++i) {
    const double da = sa[i] - az, de = se[i] - el;
    d2[i] = da * da + de * de;
  }
  // The previous answer's k samples are within `bound` of this query, so its k nearest are too.
  double bound = INFINITY;
  if (last_.size() == k) {
    bound = 0.0;
    for (const int p : last_)
      bound = std::max(bound, d2[p]);
  }
  // The candidates under the bound, compacted without a branch (whether a candidate passes is
  // unpredictable, and a mispredicted branch per candidate cost more than the test).
  int* __restrict const passed = passed_.data();
  std::size_t n = 0;
  for (std::size_t i = 0; i < m; ++i) {
    passed[n] = static_cast<int>(i);
    n += d2[i] <= bound;
  }
  // Inserted by shifting into a sorted list: k is small and few candidates pass. (Swapping two
  // adjacent ints compiled to an overlapping 8-byte rotate in memory, a store-forwarding stall.)
  std::size_t found = 0;
  for (std::size_t q = 0; q < n; ++q) {
    const int i = passed[q];
    const Candidate candidate{d2[i], index_[i], i};
    std::size_t j = found;
    if (found == k) {
      if (!(candidate < best_[k - 1])) continue;
      j = k - 1;
    } else {
      ++found;
    }
    for (; j > 0 && candidate < best_[j - 1]; --j)
      best_[j] = best_[j - 1];
    best_[j] = candidate;
  }
  last_.resize(found);
  for (std::size_t j = 0; j < found; ++j) {
    out.emplace_back(best_[j].distance2, best_[j].index);
    last_[j] = best_[j].position;
  }
}

}  // namespace multimodal_nvs
