#include "multimodal_nvs/core/depth/depth_shift.hpp"

#include <algorithm>
#include <cmath>

namespace multimodal_nvs {

double computeShift(const DepthShift& shift, const std::vector<AngularSample>& samples) {
  switch (shift.mode) {
    case DepthShift::Mode::kNone:
      return 0.0;
    case DepthShift::Mode::kValue:
      return shift.value;
    case DepthShift::Mode::kMedian:
    case DepthShift::Mode::kMean:
      break;
  }
  std::vector<double> depths;
  depths.reserve(samples.size());
  for (const auto& s : samples) {
    if (std::isfinite(s.depth) && s.depth > 0.0f) depths.push_back(s.depth);
  }
  if (depths.empty()) return 0.0;
  if (shift.mode == DepthShift::Mode::kMean) {
    double sum = 0.0;
    for (double d : depths)
      sum += d;
    return sum / depths.size();
  }
  const std::size_t mid = depths.size() / 2;
  std::nth_element(depths.begin(), depths.begin() + mid, depths.end());
  const double upper = depths[mid];
  if (depths.size() % 2 == 1) return upper;
  const double lower = *std::max_element(depths.begin(), depths.begin() + mid);
  return 0.5 * (lower + upper);  // numpy's median of an even count
}

}  // namespace multimodal_nvs
