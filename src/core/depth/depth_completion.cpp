#include "multimodal_nvs/core/depth/depth_completion.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "multimodal_nvs/core/common/buffer_reuse.hpp"
#include "multimodal_nvs/core/common/elapsed.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/vectorisable_math.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_shift.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/models/image_guided_model.hpp"
#include "multimodal_nvs/core/depth/models/model_registry.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/neighbour_sets.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/retention.hpp"

namespace multimodal_nvs {

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
    double u = 0, v = 0;
    if (!k.project(p.x(), p.y(), p.z(), &u, &v)) continue;
    count += u >= 0.0 && v >= 0.0 && u < image.width && v < image.height;
  }
  return count;
}

// The passes below are separate functions with restrict pointers: inside the lambdas the byte
// stores may alias the captured sizes and pointers, and GCC then keeps them scalar (measured 12% of
// the kernel model's time before).

/// candidate[i] = finite variance <= threshold and finite mean; returns the count of finite
/// variances (pixels the model predicted). Branch-free (bitwise &) so that it vectorises.
long long markCandidates(const float* __restrict mean, const float* __restrict variance,
                         std::size_t count, float threshold, std::uint8_t* __restrict candidate) {
  long long predicted = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const float v = variance[i], m = mean[i];
    const bool finite_v = isFiniteVectorisable(v);
    const bool finite_m = isFiniteVectorisable(m);
    predicted += finite_v;
    candidate[i] = finite_v & (v <= threshold) & finite_m;
  }
  return predicted;
}

/// depth = -1 where not kept (the reference's invalid value); returns the kept count.
long long maskDepth(const std::uint8_t* __restrict valid, std::size_t count,
                    float* __restrict depth) {
  long long kept = 0;
  for (std::size_t i = 0; i < count; ++i) {
    depth[i] = valid[i] ? depth[i] : -1.0f;
    kept += valid[i];
  }
  return kept;
}

}  // namespace

DepthMap DepthCompleter::complete(const std::vector<Eigen::Vector3d>& points_camera,
                                  const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                                  const DepthCompletionParams& params, const cv::Mat& image) {
  DepthMap out;
  complete(points_camera, intrinsics, grid, params, out, image);
  return out;
}

void DepthCompleter::complete(const std::vector<Eigen::Vector3d>& points_camera,
                              const PinholeIntrinsics& intrinsics, const StrideGrid& grid,
                              const DepthCompletionParams& params, DepthMap& out,
                              const cv::Mat& image) {
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
      toAngularSamples(points_camera, &stats.points_non_finite, pool_.get());
  stats.shift = computeShift(params.shift, samples);

  const PixelAngleGrid& angles = pixelAngles(intrinsics, grid);
  // One huge frame must not pin its work buffers for the rest of the run.
  const std::size_t pixels = static_cast<std::size_t>(grid.size());
  if (capacityFarExceeds(model_scratch_.longest_edge.capacity(), pixels) ||
      capacityFarExceeds(model_scratch_.filled.capacity(), pixels) ||
      capacityFarExceeds(model_scratch_.model_prior.mean.capacity(), pixels)) {
    model_scratch_ = ModelScratch{};
  }
  // The models write into the output's own buffers (capacity reused across calls).
  PixelPredictions prediction;
  prediction.mean.swap(out.depth);
  prediction.variance.swap(out.variance);
  GroundChoice ground;
  ImageGuidedReport guided;
  stats.neighbour_sets = predictWithModel(samples, angles, params, stats.shift, *pool_, prediction,
                                          image, &ground, &model_scratch_, &guided);
  stats.guided_return_density = guided.return_density;
  stats.guided_prior_weight = guided.prior_weight;
  stats.guided_band_top_deg = guided.band_top_deg;
  if (params.model == DepthModel::kGroundGp || params.model == DepthModel::kImageGuided) {
    stats.ground_source = toString(ground.source);
    stats.ground_mode = ground.dense ? "dense" : ground.tiled_residual ? "sparse_tiled" : "sparse";
    stats.ground_inlier_fraction = ground.inlier_fraction;
    stats.ground_scan_line_share = ground.scan_line_share;
    stats.ground_hidden_returns = ground.hidden_returns;
    stats.ground_edge_ratio = ground.edge_ratio;
    stats.ground_single_scan_plane = ground.single_scan_plane;
    stats.ground_camera_height = ground.plane.height;
    stats.ground_pitch_deg = ground.plane.pitchDeg();
    stats.ground_roll_deg = ground.plane.rollDeg();
  }

  // Valid as the reference defines it, then retention among the valid pixels. Full-image passes
  // are split into chunks whose counts are summed afterwards (deterministic for any thread count).
  // Retention's first and last pass over the pixels (see VarianceSelection) run in the same chunk
  // loops as marking the candidates and masking the depth, on chunks still in cache.
  const std::size_t n = static_cast<std::size_t>(grid.size());
  const bool retention = params.retain_percent < 100.0;
  out.valid.resize(n);
  if (retention) candidate_.resize(n);
  const float threshold = static_cast<float>(params.var_threshold);
  constexpr std::size_t kChunk = VarianceSelection::kChunk;
  const long long chunks = static_cast<long long>((n + kChunk - 1) / kChunk);
  std::vector<long long> predicted_in_chunk(chunks, 0), kept_in_chunk(chunks, 0);
  float* const depth = prediction.mean.data();
  const float* const variance = prediction.variance.data();
  std::uint8_t* const valid = out.valid.data();
  std::uint8_t* const candidate = retention ? candidate_.data() : valid;
  std::unique_ptr<VarianceSelection> selection;
  if (retention) selection = std::make_unique<VarianceSelection>(n, pool_->size());
  pool_->parallelFor(chunks, [&](long long c, int worker) {
    const std::size_t begin = static_cast<std::size_t>(c) * kChunk;
    const std::size_t count = std::min(n, begin + kChunk) - begin;
    predicted_in_chunk[c] =
        markCandidates(depth + begin, variance + begin, count, threshold, candidate + begin);
    if (retention) {
      selection->count(c, worker, variance, candidate);
    } else {  // every candidate is kept
      kept_in_chunk[c] = maskDepth(valid + begin, count, depth + begin);
    }
  });
  if (retention) {
    selection->select(retentionCount(params.retain_percent, grid.size()), variance, candidate,
                      pool_.get());
    pool_->parallelFor(chunks, [&](long long c, int) {
      const std::size_t begin = static_cast<std::size_t>(c) * kChunk;
      selection->mark(c, variance, candidate, valid);
      kept_in_chunk[c] =
          maskDepth(valid + begin, std::min(n, begin + kChunk) - begin, depth + begin);
    });
  }
  out.depth.swap(prediction.mean);
  out.variance.swap(prediction.variance);
  stats.predicted = 0;
  stats.kept = 0;
  for (long long c = 0; c < chunks; ++c) {
    stats.predicted += predicted_in_chunk[c];
    stats.kept += kept_in_chunk[c];
  }
  stats.pixels = grid.size();
  stats.compute_ms = millisecondsSince(start);
}

}  // namespace multimodal_nvs
