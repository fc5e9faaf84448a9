#include "multimodal_nvs/core/depth/models/constant_model.hpp"

// `constant` baseline: the median depth of the samples seen by the camera, everywhere.
#include <algorithm>
#include <limits>

#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

void predictConstant(const std::vector<AngularSample>& all_samples, const PixelAngleGrid& angles,
                     const DepthCompletionParams& /*params*/, ThreadPool& /*pool*/,
                     PixelPredictions& out) {
  const std::size_t n = static_cast<std::size_t>(angles.grid().size());
  const std::vector<AngularSample> samples = usableSamples(all_samples);
  const PinholeIntrinsics& k = angles.intrinsics();
  const ImageSize& image = angles.grid().image;
  std::vector<double> depths;
  for (const AngularSample& s : samples) {
    double u = 0, v = 0;
    if (angularToPixel(k, s.azimuth_deg, s.elevation_deg, &u, &v) && u >= 0 && v >= 0 &&
        u < image.width && v < image.height) {
      depths.push_back(s.depth);
    }
  }
  if (depths.empty()) {
    for (const AngularSample& s : samples)
      depths.push_back(s.depth);
  }
  if (depths.empty()) {
    setNoPrediction(angles.grid(), out);
    return;
  }
  double sum = 0.0;
  for (double d : depths)
    sum += d;
  const double mean = sum / depths.size();
  double ss = 0.0;
  for (double d : depths)
    ss += (d - mean) * (d - mean);
  const double variance = depths.size() > 1 ? ss / (depths.size() - 1) : 0.0;
  const std::size_t mid = depths.size() / 2;
  std::nth_element(depths.begin(), depths.begin() + mid, depths.end());
  double median = depths[mid];
  if (depths.size() % 2 == 0) {
    median = 0.5 * (median + *std::max_element(depths.begin(), depths.begin() + mid));
  }
  out.mean.assign(n, static_cast<float>(median));
  out.variance.assign(n, static_cast<float>(variance));
}

}  // namespace multimodal_nvs
