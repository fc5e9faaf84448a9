#include "multimodal_nvs/core/depth/angular_bins.hpp"

namespace multimodal_nvs {

AngularBins::AngularBins(const std::vector<AngularSample>& samples, double bin_deg)
    : bin_(bin_deg) {
  if (samples.empty()) return;
  min_az_ = max_az_ = samples[0].azimuth_deg;
  min_el_ = max_el_ = samples[0].elevation_deg;
  for (const auto& s : samples) {
    min_az_ = std::min<double>(min_az_, s.azimuth_deg);
    max_az_ = std::max<double>(max_az_, s.azimuth_deg);
    min_el_ = std::min<double>(min_el_, s.elevation_deg);
    max_el_ = std::max<double>(max_el_, s.elevation_deg);
  }
  nx_ = static_cast<int>((max_az_ - min_az_) / bin_) + 1;
  ny_ = static_cast<int>((max_el_ - min_el_) / bin_) + 1;
  start_.assign(std::size_t(nx_) * ny_ + 1, 0);
  for (const auto& s : samples)
    ++start_[binOf(s) + 1];
  for (std::size_t b = 1; b < start_.size(); ++b)
    start_[b] += start_[b - 1];
  order_.resize(samples.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < samples.size(); ++i)
    order_[fill[binOf(samples[i])]++] = int(i);
  binned_az_.resize(order_.size());
  binned_el_.resize(order_.size());
  for (std::size_t k = 0; k < order_.size(); ++k) {
    binned_az_[k] = samples[order_[k]].azimuth_deg;
    binned_el_[k] = samples[order_[k]].elevation_deg;
  }
}

std::size_t AngularBins::binOf(const AngularSample& s) const {
  const int x = std::min(nx_ - 1, static_cast<int>((s.azimuth_deg - min_az_) / bin_));
  const int y = std::min(ny_ - 1, static_cast<int>((s.elevation_deg - min_el_) / bin_));
  return std::size_t(y) * nx_ + x;
}

void AngularBins::collect(double az, double el, double reach, std::size_t k, double bound,
                          std::vector<std::pair<double, int>>& out) const {
  out.clear();
  if (order_.empty()) return;
  const auto [y0, y1] = binSpan(el - reach, el + reach, min_el_, ny_);
  if (y0 > y1) return;
  // Nothing at a squared distance above `limit` can enter: beyond the disc of radius `reach` (the
  // caller accepts the result only if the k-th distance is within it), beyond `bound`, or, once k
  // are found, beyond the k-th. Widened far above the rounding of the bins' edges, so that a
  // sample at exactly the k-th distance (a tie, decided by index) is still visited.
  const double reach2 = reach * reach;
  const auto limit = [&] {
    double c = std::min(reach2, bound);
    if (out.size() == k) c = std::min(c, out.back().first);
    return c * (1.0 + 1e-9) + 1e-12;
  };
  // One bin row, walked only across the disc's chord at the row's nearest elevation to the query
  // (a square walk visits 4/pi times the samples). False when the row lies beyond the limit, and
  // with it every row farther from the query.
  const auto walk_row = [&](int y) {
    const double row_lo = min_el_ + y * bin_, row_hi = row_lo + bin_;
    const double dy = el < row_lo ? row_lo - el : (el > row_hi ? el - row_hi : 0.0);
    const double c = limit();
    if (dy * dy > c) return false;
    const double half = std::sqrt(c - dy * dy);
    const auto [x0, x1] = binSpan(az - half, az + half, min_az_, nx_);
    if (x0 > x1) return true;
    const std::size_t first = std::size_t(y) * nx_;
    // The k smallest (distance, index) pairs are kept sorted by insertion: k is small (8) and
    // most candidates fail the first comparison, where collecting every candidate and
    // partitioning them (nth_element) mispredicted its branches.
    for (int b = start_[first + x0]; b < start_[first + x1 + 1]; ++b) {
      const double da = binned_az_[b] - az, de = binned_el_[b] - el;
      const std::pair<double, int> candidate(da * da + de * de, order_[b]);
      if (candidate.first > bound) continue;
      if (out.size() == k) {
        if (!(candidate < out.back())) continue;
        out.back() = candidate;
      } else {
        out.push_back(candidate);
      }
      for (std::size_t i = out.size() - 1; i > 0 && out[i] < out[i - 1]; --i)
        std::swap(out[i], out[i - 1]);
    }
    return true;
  };
  // Rows outward from the query's own, alternately below and above: once k are found, the k-th
  // distance stops the walk early (a query above the top scan line used to walk every row of
  // the disc, though the answer lies in the first).
  int below = std::clamp(static_cast<int>(std::floor((el - min_el_) / bin_)), y0, y1);
  int above = below + 1;
  bool more_below = true, more_above = above <= y1;
  while (more_below || more_above) {
    if (more_below) more_below = walk_row(below) && --below >= y0;
    if (more_above) more_above = walk_row(above) && ++above <= y1;
  }
}

void AngularBins::nearest(double az, double el, int k, std::vector<std::pair<double, int>>& out,
                          double start_reach) const {
  out.clear();
  if (order_.empty() || k <= 0) return;
  const std::size_t kk = static_cast<std::size_t>(k);
  // Grow the search radius until k samples lie within it (then nothing outside can be nearer), or
  // until it covers every sample.
  const double extent = std::max({max_az_ - min_az_, max_el_ - min_el_, bin_}) +
                        std::abs(az - min_az_) + std::abs(el - min_el_);
  for (double reach = std::max(bin_, start_reach);; reach *= 2.0) {
    const bool covers_all = reach > extent;
    // The answer stands only if the k-th distance is within reach, so nothing beyond reach needs
    // sorting in (the bins of the walk hold such samples too); the last round keeps everything.
    collect(az, el, reach, kk, covers_all ? INFINITY : reach * reach, out);
    if (out.empty() && !covers_all) continue;
    if (out.empty()) return;
    if ((out.size() == kk && out.back().first <= reach * reach) || covers_all) return;
  }
}

}  // namespace multimodal_nvs
