#pragma once
// The constant the targets are centred on before regression (y = z - shift).
#include <vector>
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"

namespace multimodal_nvs {

/// The centring value for `DepthShift` over the depths of all finite points with z > 0 (0 if none).
double computeShift(const DepthShift& shift, const std::vector<AngularSample>& samples);

}  // namespace multimodal_nvs
