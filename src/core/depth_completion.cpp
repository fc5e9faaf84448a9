#include "multimodal_nvs/core/depth_completion.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "multimodal_nvs/core/baselines.hpp"
#include "multimodal_nvs/core/depth_models.hpp"
#include "multimodal_nvs/core/errors.hpp"
#include "multimodal_nvs/core/ground_prior.hpp"
#include "multimodal_nvs/core/neighbour_sets.hpp"
#include "multimodal_nvs/core/retention.hpp"

namespace multimodal_nvs {

double computeShift(const DepthShift& shift, const std::vector<AngularSample>& samples) {
  switch (shift.mode) {
    case DepthShift::Mode::kNone:
      return 0.0;
    case DepthShift::Mode::kValue:
      return shift.value;
    case DepthShift::Mode::kMedian:
    case DepthShift::Mode::kMean:
      break;
  }
  std::vector<double> depths;
  depths.reserve(samples.size());
  for (const auto& s : samples) {
    if (std::isfinite(s.depth) && s.depth > 0.0f) depths.push_back(s.depth);
  }
  if (depths.empty()) return 0.0;
  if (shift.mode == DepthShift::Mode::kMean) {
    double sum = 0.0;
    for (double d : depths) sum += d;
    return sum / depths.size();
  }
  const std::size_t mid = depths.size() / 2;
  std::nth_element(depths.begin(), depths.begin() + mid, depths.end());
  const double upper = depths[mid];
  if (depths.size() % 2 == 1) return upper;
  const double lower = *std::max_element(depths.begin(), depths.begin() + mid);
  return 0.5 * (lower + upper);  // numpy's median of an even count
}

DepthCompleter::DepthCompleter(int threads) : pool_(std::make_unique<ThreadPool>(threads)) {}

const PixelAngleGrid& DepthCompleter::pixelAngles(const PinholeIntrinsics& intrinsics,
                                                  const StrideGrid& grid) {
  if (!angles_ || !angles_->matches(intrinsics, grid)) {
    angles_ = std::make_unique<PixelAngleGrid>(intrinsics, grid);
  }
  return *angles_;
}

namespace {
std::size_t countInView(const std::vector<Eigen::Vector3d>& points, const PinholeIntrinsics& k,
                        const ImageSize& image) {
  std::size_t count = 0;
  for (const auto& p : points) {
    if (!p.allFinite() || !(p.z() > 0.0)) continue;
    const double u = k.fx * p.x() / p.z() + k.cx;
    const double v = k.fy * p.y() / p.z() + k.cy;
    count += u >= 0.0 && v >= 0.0 && u < image.width && v < image.height;
  }
  return count;
}
}  // namespace

DepthMap DepthCompleter::complete(const std::vector<Eigen::Vector3d>& points_camera,
                                  const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                                  const DepthCompletionParams& params) {
  DepthMap out;
  complete(points_camera, intrinsics, grid, params, out);
  return out;
}

void DepthCompleter::complete(const std::vector<Eigen::Vector3d>& points_camera,
                              const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                              const DepthCompletionParams& params, DepthMap& out) {
  params.validate();
  intrinsics.validate("camera intrinsics");
  if (grid.image.height <= 0 || grid.image.width <= 0 || grid.stride < 1) {
    throw InputError("image size must be positive and stride >= 1");
  }
  const auto start = std::chrono::steady_clock::now();
  out.grid = grid;
  out.stats = {};
  DepthMapStats& stats = out.stats;
  stats.points_total = points_camera.size();
  stats.points_in_view = countInView(points_camera, intrinsics, grid.image);
  const std::vector<AngularSample> samples =
      toAngularSamples(points_camera, &stats.points_non_finite);
  stats.shift = computeShift(params.shift, samples);

  const PixelAngleGrid& angles = pixelAngles(intrinsics, grid);
  // The models write into the output's own buffers (capacity reused across calls).
  PixelPredictions prediction;
  prediction.mean.swap(out.depth);
  prediction.variance.swap(out.variance);
  if (isBaseline(params.model)) {
    predictBaseline(samples, angles, params, *pool_, prediction);  // no neighbour sets needed
  } else if (params.model == DepthModel::kLocalGpMle && params.max_neighbors > 0) {
    stats.neighbour_sets = predictTiledLocalGp(samples, angles, params, stats.shift, *pool_,
                                               prediction);
  } else {
    const NeighbourSets sets = NeighbourSets::build(
        samples, angles, static_cast<float>(params.radius_deg), *pool_);
    stats.neighbour_sets = sets.setCount();
    if (params.model == DepthModel::kLocalGpMle) {
      predictLocalGp(samples, angles, sets, params, stats.shift, *pool_, prediction);
    } else if (params.model == DepthModel::kGroundGp) {
      GroundPlane plane;
      plane.up = Eigen::Vector3d(params.ground.up_x, params.ground.up_y, params.ground.up_z)
                     .normalized();
      plane.height = params.ground.camera_height;
      const double median = computeShift(DepthShift{}, samples);
      predictGroundGp(samples, angles, sets, params, plane, median, *pool_, prediction);
    } else {
      predictKernel(samples, angles, sets, params, stats.shift, *pool_, prediction);
    }
  }

  // Valid as the reference defines it, then retention among the valid pixels.
  const std::size_t n = static_cast<std::size_t>(grid.size());
  const bool retention = params.retain_percent < 100.0;
  std::vector<std::uint8_t>& candidate = retention ? candidate_ : out.valid;
  candidate.resize(n);
  const float threshold = static_cast<float>(params.var_threshold);
  // Full-image passes split into chunks; per-chunk counts are summed afterwards (deterministic).
  constexpr std::size_t kChunk = 1 << 16;
  const long long chunks = static_cast<long long>((n + kChunk - 1) / kChunk);
  std::vector<long long> chunk_count(chunks, 0);
  pool_->parallelFor(chunks, [&](long long c, int) {
    // Branch-free (bitwise &, not &&) so that the loop vectorises.
    long long predicted = 0;
    const float* variance = prediction.variance.data();
    const float* mean = prediction.mean.data();
    std::uint8_t* is_candidate = candidate.data();
    for (std::size_t i = c * kChunk; i < std::min<std::size_t>(n, (c + 1) * kChunk); ++i) {
      const float v = variance[i], m = mean[i];
      const bool finite_v = std::abs(v) <= std::numeric_limits<float>::max();
      const bool finite_m = std::abs(m) <= std::numeric_limits<float>::max();
      predicted += finite_v;
      is_candidate[i] = finite_v & (v <= threshold) & finite_m;
    }
    chunk_count[c] = predicted;
  });
  stats.predicted = 0;
  for (long long c : chunk_count) stats.predicted += c;
  if (retention) {
    out.valid.resize(n);
    keepLowestVariance(prediction.variance.data(), candidate.data(), n,
                       retentionCount(params.retain_percent, grid.size()), out.valid.data());
  }
  out.depth.swap(prediction.mean);
  out.variance.swap(prediction.variance);
  pool_->parallelFor(chunks, [&](long long c, int) {
    long long kept = 0;
    float* depth = out.depth.data();
    const std::uint8_t* valid = out.valid.data();
    for (std::size_t i = c * kChunk; i < std::min<std::size_t>(n, (c + 1) * kChunk); ++i) {
      depth[i] = valid[i] ? depth[i] : -1.0f;
      kept += valid[i];
    }
    chunk_count[c] = kept;
  });
  stats.kept = 0;
  for (long long c : chunk_count) stats.kept += c;
  stats.pixels = grid.size();
  stats.compute_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace multimodal_nvs
