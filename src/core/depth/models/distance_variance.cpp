#include "multimodal_nvs/core/depth/models/distance_variance.hpp"

namespace multimodal_nvs {

double distanceVariance(double distance_deg, const DepthCompletionParams& params) {
  const double sigma = params.gp.noise, a = params.gp.amplitude;
  const double l = params.kernel_length_scale_deg;
  const double ratio = distance_deg / l;
  return sigma * sigma + a * a * ratio * ratio;
}

}  // namespace multimodal_nvs
