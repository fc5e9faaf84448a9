#include "multimodal_nvs/core/depth/angular_bins.hpp"

namespace multimodal_nvs {

AngularBins::AngularBins(const std::vector<AngularSample>& samples, double bin_deg)
    : samples_(&samples), bin_(bin_deg) {
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
}

std::size_t AngularBins::binOf(const AngularSample& s) const {
  const int x = std::min(nx_ - 1, static_cast<int>((s.azimuth_deg - min_az_) / bin_));
  const int y = std::min(ny_ - 1, static_cast<int>((s.elevation_deg - min_el_) / bin_));
  return std::size_t(y) * nx_ + x;
}

void AngularBins::nearest(double az, double el, int k, std::vector<std::pair<double, int>>& out,
                          double start_reach) const {
  out.clear();
  if (order_.empty() || k <= 0) return;
  const std::vector<AngularSample>& samples = *samples_;
  // Grow the searched square until it holds k samples whose k-th distance is inside the square
  // (then nothing outside can be nearer), or until it covers every sample.
  const double extent = std::max({max_az_ - min_az_, max_el_ - min_el_, bin_}) +
                        std::abs(az - min_az_) + std::abs(el - min_el_);
  for (double reach = std::max(bin_, start_reach);; reach *= 2.0) {
    out.clear();
    query(az, el, reach, [&](int i) {
      const double da = samples[i].azimuth_deg - az, de = samples[i].elevation_deg - el;
      out.emplace_back(da * da + de * de, i);
    });
    const std::size_t kk = std::min<std::size_t>(k, out.size());
    const bool covers_all = reach > extent;
    if (kk == 0 && !covers_all) continue;
    if (kk == 0) return;
    std::nth_element(out.begin(), out.begin() + (kk - 1), out.end());
    out.resize(kk);
    if ((kk == static_cast<std::size_t>(k) && out.back().first <= reach * reach) || covers_all) {
      std::iter_swap(out.begin(), std::min_element(out.begin(), out.end()));
      return;
    }
  }
}

}  // namespace multimodal_nvs
