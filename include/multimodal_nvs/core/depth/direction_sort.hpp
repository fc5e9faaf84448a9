#pragma once
// Angular samples in the order of their directions, for passes that merge repeated directions.
#include <vector>

#include "multimodal_nvs/core/depth/angular_samples.hpp"

namespace multimodal_nvs {

/// Sorts finite samples by (elevation, azimuth, depth), each compared as a float (so -0 and +0
/// are one angle): the order std::sort with that comparison gives (samples equal in all three are
/// the same sample, so the result is unique).
void sortByDirectionThenDepth(std::vector<AngularSample>& samples);

}  // namespace multimodal_nvs
