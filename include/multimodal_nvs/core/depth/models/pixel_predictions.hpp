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
