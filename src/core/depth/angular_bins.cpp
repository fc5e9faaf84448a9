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
  // The k smallest (distance, index) pairs are kept sorted by insertion: k is small (8) and most
  // candidates fail the first comparison, where collecting every candidate and partitioning them
  // (nth_element) mispredicted its branches. Each bin row is walked only across the disc of radius
  // `reach`: at the row's nearest elevation to the query the disc is 2 sqrt(reach^2 - dy^2) wide
  // (a square walk visits 4/pi times the samples). Samples outside the disc are farther than
  // reach, and the caller accepts the result only if the k-th distance is within reach, so
  // skipping them changes nothing.
  forEachDiscRow(az, el, reach, [&](int begin, int end) {
    for (int b = begin; b < end; ++b) {
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
  });
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
