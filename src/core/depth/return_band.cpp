#include "multimodal_nvs/core/depth/return_band.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace multimodal_nvs {

float returnBandTop(std::vector<float> elevations, double top_share) {
  if (elevations.empty()) return std::nanf("");
  const double share = std::clamp(top_share, 0.0, 1.0);
  const std::size_t rank =
      std::min(elevations.size() - 1, static_cast<std::size_t>(share * double(elevations.size())));
  std::nth_element(elevations.begin(), elevations.begin() + rank, elevations.end(),
                   std::greater<float>());
  return elevations[rank];
}

}  // namespace multimodal_nvs
