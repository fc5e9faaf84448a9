#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"

#include <algorithm>
#include <limits>

namespace multimodal_nvs {

void setNoPrediction(const StrideGrid& grid, PixelPredictions& out) {
  const std::size_t pixels = static_cast<std::size_t>(grid.size());
  out.mean.assign(pixels, std::numeric_limits<float>::quiet_NaN());
  out.variance.assign(pixels, kNoPrediction);
}

void fillPredictions(const PixelAngleGrid& angles, float mean, float variance, ThreadPool& pool,
                     PixelPredictions& out) {
  const std::size_t n = static_cast<std::size_t>(angles.grid().size());
  out.mean.resize(n);
  out.variance.resize(n);
  constexpr std::size_t kChunk = 1 << 16;
  pool.parallelFor(static_cast<long long>((n + kChunk - 1) / kChunk), [&](long long chunk, int) {
    const std::size_t begin = static_cast<std::size_t>(chunk) * kChunk;
    const std::size_t end = std::min(n, begin + kChunk);
    std::fill(out.mean.begin() + begin, out.mean.begin() + end, mean);
    std::fill(out.variance.begin() + begin, out.variance.begin() + end, variance);
  });
}

}  // namespace multimodal_nvs
