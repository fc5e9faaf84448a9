#include "multimodal_nvs/core/depth/region_nearest.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

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
  order_.resize(index_.size());
  passed_.resize(index_.size());
  in_head_.resize(index_.size());
  head_ = 0;
  return bound;
}

void RegionNearest::nearest(double az, double el, std::size_t k,
                            std::vector<std::pair<double, int>>& out) {
  out.clear();
  const std::size_t m = index_.size();
  if (k == 0 || m == 0) return;
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
  // `order_` holds the previous query's answer, nearest first (after a gather or with another k:
  // the first k gathered). A query's neighbour is a pixel or two away, so that answer
  // is nearly this one's: it is re-sorted by insertion (mostly without a move), and another
  // sample enters only when it beats the answer's last. Exact for any starting answer; the near
  // start only makes the branches predictable (a fresh insertion sort of the candidates under a
  // bound mispredicted about once per candidate).
  const int* __restrict const index = index_.data();
  const auto before = [&](int a, int b) {
    return d2[a] < d2[b] || (d2[a] == d2[b] && index[a] < index[b]);
  };
  const std::size_t head = std::min(k, m);
  int* const order = order_.data();
  std::uint8_t* __restrict const in_head = in_head_.data();
  if (head != head_) {
    // A new region or another k: any distinct start will do (only the first head_ entries of
    // order_ are kept up to date).
    std::fill(in_head_.begin(), in_head_.end(), std::uint8_t{0});
    for (std::size_t j = 0; j < head; ++j) {
      order[j] = static_cast<int>(j);
      in_head[j] = 1;
    }
    head_ = head;
  }
  for (std::size_t j = 1; j < head; ++j) {
    const int p = order[j];
    std::size_t i = j;
    for (; i > 0 && before(p, order[i - 1]); --i)
      order[i] = order[i - 1];
    order[i] = p;
  }
  // The others that may enter: within the answer's last distance (it only shrinks as samples
  // enter), listed without a branch (whether one passes is unpredictable), then decided exactly.
  const double worst = d2[order[head - 1]];
  int* __restrict const passed = passed_.data();
  std::size_t n = 0;
  for (std::size_t i = 0; i < m; ++i) {
    passed[n] = static_cast<int>(i);
    n += (d2[i] <= worst) & (in_head[i] == 0);
  }
  for (std::size_t q = 0; q < n; ++q) {
    const int p = passed[q];
    if (!before(p, order[head - 1])) continue;
    in_head[order[head - 1]] = 0;
    in_head[p] = 1;
    std::size_t i = head - 1;
    for (; i > 0 && before(p, order[i - 1]); --i)
      order[i] = order[i - 1];
    order[i] = p;
  }
  for (std::size_t j = 0; j < head; ++j)
    out.emplace_back(d2[order[j]], index[order[j]]);
}

}  // namespace multimodal_nvs
