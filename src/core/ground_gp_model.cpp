// The `ground_gp` model (beyond the paper). The reference GP falls back to a plane at the scan's
// median depth wherever no sample lies within 2 deg, and regresses the depth itself elsewhere, so
// far returns (radar multipath, returns through vegetation, the far side of objects) pull every
// estimate back. Here the prior mean is physical:
//   prior(p) = min(ground depth along p, nearest-surface depth at p)
// - nothing along a descending ray can be farther than where it meets the ground;
// - the nearest-surface depth is a low order statistic of the k angularly nearest samples, so
//   the first surface along the ray wins, as it does for a camera, and every pixel has support.
// The local GP (same neighbour sets and length-scale search as the reference) then models the
// residual between the samples and that prior with a small amplitude, and the variance adds the
// prior's own uncertainty, which grows with the angular distance to the nearest sample.
#include <algorithm>
#include <cmath>

#include "multimodal_nvs/core/depth_models.hpp"
#include "multimodal_nvs/core/ground_prior.hpp"

namespace multimodal_nvs {
namespace {
// A return within this fraction of the ground depth along its ray counts as a ground return.
constexpr double kGroundMargin = 0.1;
}  // namespace

void predictGroundGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const NeighbourSets& sets, const DepthCompletionParams& params,
                     const GroundPlane& plane, double median_depth, ThreadPool& pool,
                     PixelPredictions& out) {
  const GroundPriorParams& g = params.ground;
  const double far = g.far_depth > 0.0 ? g.far_depth : std::max(median_depth, 1.0);
  const int step = std::max(1, g.surface_step_px / angles.grid().stride);
  // Returns from the ground itself say nothing about objects, and on a slanted surface such as the
  // road a low order statistic would pick the nearer ground returns of lower rows; so only
  // returns clearly in front of the ground (or above the horizon) shape the surface prior.
  std::vector<AngularSample> objects;
  for (const auto& sample : samples) {
    const Eigen::Vector2d ray = normalisedFromAngles(sample.azimuth_deg, sample.elevation_deg);
    if (sample.depth < (1.0 - kGroundMargin) * plane.depthAlong(ray.x(), ray.y())) {
      objects.push_back(sample);
    }
  }
  const NearestSurface surface =
      nearestSurfaceDepth(objects, angles, g.surface_k, g.surface_rank, step, pool);
  // The prior's uncertainty grows with the distance to the nearest return of any kind.
  const std::vector<float> support_distance =
      objects.size() == samples.size()
          ? surface.distance_deg
          : nearestSurfaceDepth(samples, angles, 1, 1, step, pool).distance_deg;
  // The far value only where neither the ground nor any sample bounds the depth.
  std::vector<float> prior = groundPriorDepth(angles, plane, INFINITY);
  const long long rows = angles.grid().rows();
  const std::size_t cols = static_cast<std::size_t>(angles.grid().cols());
  pool.parallelFor(rows, [&](long long r, int) {
    for (std::size_t p = r * cols; p < (r + 1) * cols; ++p) {
      prior[p] = std::min(prior[p], surface.depth[p]);
      if (!std::isfinite(prior[p])) prior[p] = static_cast<float>(far);
    }
  }, 16);

  if (g.residual_amplitude > 0.0) {
    // The prior at each sample's own direction: ground capped by the surface estimate of the
    // nearest grid pixel (the lattice is only known on the grid).
    const PinholeIntrinsics& k = angles.intrinsics();
    const StrideGrid& grid = angles.grid();
    std::vector<double> residual(samples.size(), 0.0);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const Eigen::Vector2d ray =
          normalisedFromAngles(samples[i].azimuth_deg, samples[i].elevation_deg);
      const int c = static_cast<int>(std::lround((k.fx * ray.x() + k.cx) / grid.stride));
      const int r = static_cast<int>(std::lround((k.fy * ray.y() + k.cy) / grid.stride));
      double at_sample = plane.depthAlong(ray.x(), ray.y());
      if (r >= 0 && c >= 0 && r < grid.rows() && c < grid.cols()) {
        at_sample = std::min<double>(at_sample, surface.depth[std::size_t(r) * grid.cols() + c]);
      }
      // A return behind the prior surface is an occluded or multipath return: it says nothing
      // about the first surface, so it only confirms the prior (residual 0). A nearer return
      // reveals a surface in front of the prior and pulls the prediction towards it.
      // Residuals beyond 3 GP standard deviations are clipped (a Huber-like robust target), so one
      // stray near return cannot drag a neighbourhood through the camera.
      residual[i] = std::isfinite(at_sample)
                        ? std::clamp(samples[i].depth - at_sample, -3.0 * g.residual_amplitude, 0.0)
                        : 0.0;
    }
    DepthCompletionParams residual_params = params;
    residual_params.gp.amplitude = g.residual_amplitude;
    predictLocalGp(samples, residual, angles, sets, residual_params, PriorMean{0.0, &prior}, pool,
                   out);
  } else {
    out.mean = prior;
    out.variance.assign(prior.size(), 0.0f);
  }
  pool.parallelFor(rows, [&](long long r, int) {
    for (std::size_t p = r * cols; p < (r + 1) * cols; ++p) {
      // A depth is positive: the residual GP must not push a near prior through the camera.
      const float mean = std::max(out.mean[p], 0.1f);
      const float sigma = mean * static_cast<float>(g.relative_sigma + g.relative_sigma_per_deg *
                                                                           support_distance[p]);
      out.mean[p] = mean;
      out.variance[p] += sigma * sigma;
    }
  }, 16);
}

}  // namespace multimodal_nvs
