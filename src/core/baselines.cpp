#include "multimodal_nvs/core/baselines.hpp"

#include <cmath>

#include "multimodal_nvs/core/errors.hpp"

namespace multimodal_nvs {

bool isBaseline(DepthModel model) {
  switch (model) {
    case DepthModel::kNearest:
    case DepthModel::kLinear:
    case DepthModel::kIpBasic:
    case DepthModel::kConstant:
      return true;
    default:
      return false;
  }
}

void predictBaseline(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const DepthCompletionParams& params, ThreadPool& pool, PixelPredictions& out) {
  switch (params.model) {
    case DepthModel::kNearest:
      return predictNearest(samples, angles, params, pool, out);
    case DepthModel::kLinear:
      return predictLinear(samples, angles, params, pool, out);
    case DepthModel::kIpBasic:
      return predictIpBasic(samples, angles, params, pool, out);
    case DepthModel::kConstant:
      return predictConstant(samples, angles, params, pool, out);
    default:
      break;
  }
  throw InputError(std::string("model ") + toString(params.model) + " is not a baseline");
}

double distanceVariance(double distance_deg, const DepthCompletionParams& params) {
  const double sigma = params.gp.noise, a = params.gp.amplitude;
  const double l = params.kernel_length_scale_deg;
  const double ratio = distance_deg / l;
  return sigma * sigma + a * a * ratio * ratio;
}

std::vector<AngularSample> usableSamples(const std::vector<AngularSample>& samples) {
  std::vector<AngularSample> out;
  out.reserve(samples.size());
  for (const AngularSample& s : samples) {
    if (std::isfinite(s.azimuth_deg) && std::isfinite(s.elevation_deg) && std::isfinite(s.depth) &&
        s.depth > 0.0f) {
      out.push_back(s);
    }
  }
  return out;
}

bool angularToPixel(const PinholeIntrinsics& k, double azimuth_deg, double elevation_deg, double* u,
                    double* v) {
  constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
  if (!(std::abs(azimuth_deg) < 90.0) || !(std::abs(elevation_deg) < 90.0)) return false;
  const double az = azimuth_deg * kDegToRad, el = elevation_deg * kDegToRad;
  *u = k.cx + k.fx * std::tan(az);
  *v = k.cy - k.fy * std::tan(el) / std::cos(az);
  return true;
}

}  // namespace multimodal_nvs
