#pragma once
// The one mapping between the nodelet's dynamic_reconfigure Config (cfg/DepthCompletion.cfg, also
// filled from YAML through the parameter server) and the core's DepthCompletionParams.
#include <multimodal_nvs/DepthCompletionConfig.h>

#include "multimodal_nvs/core/depth/depth_params.hpp"

namespace multimodal_nvs {

/// Everything one frame needs besides its messages; the nodelet copies it once per frame.
struct DepthCompletionSettings {
  DepthCompletionParams params;
  int stride = 1;        ///< output grid step in input pixels
  int cloud_stride = 1;  ///< decimation of depth/points in grid pixels
};

/// Config -> settings. Throws InputError naming the bad parameter (unknown model, bad shift,
/// anything DepthCompletionParams::validate() rejects).
DepthCompletionSettings settingsFromConfig(const DepthCompletionConfig& config);

/// Settings -> config (the way back, used to restore the last valid values after a bad update).
void writeSettingsToConfig(const DepthCompletionSettings& settings, DepthCompletionConfig& config);

}  // namespace multimodal_nvs
