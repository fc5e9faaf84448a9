#pragma once
// What every depth model writes: a mean and a variance per output pixel.
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// Per-pixel prediction written by a model: mean (metres) and variance (m^2, +inf = no prediction).
struct PixelPredictions {
  std::vector<float> mean;
  std::vector<float> variance;
};

/// Full-image work buffers a model keeps between frames (the completer owns them): a fresh
/// full-resolution buffer costs its page faults on every frame (9.4 MB of floats at 1936x1216).
struct ModelScratch {
  std::vector<std::uint8_t> filled;  ///< ground_gp dense: pixels inside a triangle
  std::vector<float> longest_edge;   ///< ground_gp dense: longest edge (deg) of a pixel's triangle
  PixelPredictions model_prior;      ///< image_guided: ground_gp's prediction, its prior
  /// image_guided: the coarser grid of ground_gp's prior (guided.prior_step_px), the prediction
  /// on it and the interpolation's scratch.
  std::unique_ptr<PixelAngleGrid> prior_angles;
  PixelPredictions coarse_prior;
  std::vector<float> prior_upsampling;
};

/// Variance of a pixel that got no prediction.
constexpr float kNoPrediction = std::numeric_limits<float>::infinity();

/// Sizes `out` to the grid with no prediction anywhere (mean NaN, variance kNoPrediction): where a
/// model that predicts only some pixels starts.
void setNoPrediction(const StrideGrid& grid, PixelPredictions& out);

/// Sizes `out` to the grid and sets every pixel to (mean, variance), in parallel: the buffers are
/// reused across frames, so this is one full-image pass shared by both cores, not an allocation.
void fillPredictions(const PixelAngleGrid& angles, float mean, float variance, ThreadPool& pool,
                     PixelPredictions& out);

}  // namespace multimodal_nvs
