#include "multimodal_nvs/core/depth/models/linear_model.hpp"

// `linear` baseline: Delaunay triangulation of the samples in (azimuth, elevation)
// (angular_triangulation.hpp), then barycentric interpolation per grid pixel.
#include <algorithm>
#include <cmath>
#include <limits>

#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/angular_triangulation.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

void predictLinear(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                   const DepthCompletionParams& /*params*/, ThreadPool& pool,
                   PixelPredictions& out) {
  setNoPrediction(angles.grid(), out);
  const std::vector<AngularTriangle> triangles = triangulateSamples(samples, angles);
  std::vector<std::uint8_t> filled;
  rasterizeTriangles(triangles, angles, pool, filled,
                     [&](const AngularTriangle& t, double l0, double l1, double l2,
                         std::size_t pixel, float, float) {
                       const double mean = l0 * t.z[0] + l1 * t.z[1] + l2 * t.z[2];
                       const double d0 = t.z[0] - mean, d1 = t.z[1] - mean, d2 = t.z[2] - mean;
                       const double var = std::max(0.0, l0) * d0 * d0 +
                                          std::max(0.0, l1) * d1 * d1 + std::max(0.0, l2) * d2 * d2;
                       out.mean[pixel] = static_cast<float>(mean);
                       out.variance[pixel] = static_cast<float>(var);
                       return true;
                     });
}

}  // namespace multimodal_nvs
