#pragma once
// What the models keep between the frames of one completer.
#include <cstdint>
#include <memory>
#include <vector>

#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/models/prediction_upsampling.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// Full-image work buffers a model keeps between frames (the completer owns them): a fresh
/// full-resolution buffer costs its page faults on every frame (9.4 MB of floats at 1936x1216).
struct ModelScratch {
  std::vector<std::uint8_t> filled;  ///< ground_gp dense: pixels inside a triangle
  std::vector<float> longest_edge;   ///< ground_gp dense: longest edge (deg) of a pixel's triangle
  PixelPredictions model_prior;      ///< image_guided: ground_gp's prediction, its prior
  /// image_guided: the coarser grid of ground_gp's prior (guided.prior_step_px), the prediction
  /// on it and its interpolation onto the output grid (read row by row).
  std::unique_ptr<PixelAngleGrid> prior_angles;
  PixelPredictions coarse_prior;
  UpsampledPredictions upsampled_prior;
};

}  // namespace multimodal_nvs
