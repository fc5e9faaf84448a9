#include "multimodal_nvs/core/depth/models/tiled_local_gp_model.hpp"

// The approximation for dense input (max_neighbors > 0). With LiDAR a 2 deg circle holds ~200
// samples and neighbour sets almost never repeat, so the exact method needs one O(n^3) length-scale
// search per pixel. Here every tile of approx_tile x approx_tile grid pixels shares one set (the
// max_neighbors samples nearest to the tile centre, among those that can reach the tile) and one
// length scale (searched once per block of 4 x 4 tiles). A pixel with no sample of that set within
// the radius gets the prior, as in the exact method.
#include <algorithm>
#include <cmath>

#include "multimodal_nvs/core/common/per_worker.hpp"
#include "multimodal_nvs/core/depth/angular_bins.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/gp/batched_length_scale_search.hpp"
#include "multimodal_nvs/core/depth/gp/gp_prediction.hpp"
#include "multimodal_nvs/core/depth/gp/length_scale_search.hpp"
#include "multimodal_nvs/core/depth/gp/local_gp.hpp"
#include "multimodal_nvs/core/depth/models/local_gp_model.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {
namespace {

// A length scale is searched once per block of kSearchBlock x kSearchBlock tiles: the search is
// ~22 Cholesky factorisations while a tile needs only one, and the optimum varies slowly.
constexpr int kSearchBlock = 4;

struct TileWorkspace {
  explicit TileWorkspace(const LocalGpParams& p) : gp(p) {}
  LocalGp gp;
  std::vector<std::pair<double, int>> candidates;
  std::vector<float> az, el, min_d2;
  std::vector<float> pixel_az, pixel_el;  // the tile's pixels, gathered row after row
  std::vector<double> y, factor, beta;
  std::vector<float> mean, var;
};

struct TileGeometry {
  int r0, r1, c0, c1;
  double az, el, reach;
};

TileGeometry tileGeometry(const PixelAngleGrid& angles, int r0, int r1, int c0, int c1,
                          double radius) {
  TileGeometry t{r0, r1, c0, c1, 0.0, 0.0, 0.0};
  const int rc = (r0 + r1 - 1) / 2, cc = (c0 + c1 - 1) / 2;
  t.az = angles.azimuthRow(rc)[cc];
  t.el = angles.elevationRow(rc)[cc];
  double half_diagonal = 0.0;
  for (int r : {r0, r1 - 1}) {
    for (int c : {c0, c1 - 1}) {
      half_diagonal = std::max(half_diagonal, std::hypot(angles.azimuthRow(r)[c] - t.az,
                                                         angles.elevationRow(r)[c] - t.el));
    }
  }
  t.reach = radius + half_diagonal;
  return t;
}

/// Loads into `ws` the (at most `limit`) samples nearest to the tile centre among those that can
/// be within the radius of some tile pixel, in index order. Returns their number.
int loadNearestSamples(const std::vector<AngularSample>& samples,
                       const std::vector<double>& targets, const AngularBins& bins,
                       const TileGeometry& tile, int limit, TileWorkspace& ws) {
  ws.candidates.clear();
  bins.query(tile.az, tile.el, tile.reach, [&](int i) {
    const double da = samples[i].azimuth_deg - tile.az, de = samples[i].elevation_deg - tile.el;
    const double d2 = da * da + de * de;
    if (d2 <= tile.reach * tile.reach) ws.candidates.emplace_back(d2, i);
  });
  const std::size_t keep = std::min<std::size_t>(ws.candidates.size(), std::size_t(limit));
  if (keep == 0) return 0;
  std::nth_element(ws.candidates.begin(), ws.candidates.begin() + (keep - 1), ws.candidates.end());
  std::sort(ws.candidates.begin(), ws.candidates.begin() + keep,
            [](const auto& a, const auto& b) { return a.second < b.second; });
  ws.az.resize(keep);
  ws.el.resize(keep);
  ws.y.resize(keep);
  for (std::size_t k = 0; k < keep; ++k) {
    const int i = ws.candidates[k].second;
    ws.az[k] = samples[i].azimuth_deg;
    ws.el[k] = samples[i].elevation_deg;
    ws.y[k] = targets[i];
  }
  return static_cast<int>(keep);
}

/// Smallest squared angular distance from each pixel to the set (vectorised over pixels).
void minSquaredDistance(const float* az, const float* el, int pixels, const TileWorkspace& ws,
                        int n, float* __restrict out) {
  for (int p = 0; p < pixels; ++p)
    out[p] = INFINITY;
  for (int i = 0; i < n; ++i) {
    const float saz = ws.az[i], sel = ws.el[i];
    for (int p = 0; p < pixels; ++p) {
      const float da = az[p] - saz, de = el[p] - sel;
      out[p] = std::min(out[p], da * da + de * de);
    }
  }
}

/// The samples of one block's length-scale search.
struct BlockSet {
  std::vector<float> az, el;
  std::vector<double> y;
};

/// Length scale of every block's set (0 for an empty set). Sets of 3..kMaxBatchedSize samples are
/// searched kLanes at a time, grouped by size; the others one by one.
std::vector<double> searchBlockLengthScales(const std::vector<BlockSet>& sets,
                                            const LocalGpParams& gp, PredictionPrecision precision,
                                            ThreadPool& pool,
                                            PerWorker<TileWorkspace>& workspaces) {
  std::vector<double> length_scale(sets.size(), 0.0);
  const auto set_data = [&](int b) {
    return SearchSet{static_cast<int>(sets[b].y.size()), sets[b].az.data(), sets[b].el.data(),
                     sets[b].y.data()};
  };
  std::vector<int> singles = searchInEqualSizeBatches(precision, static_cast<int>(sets.size()),
                                                      set_data, gp, pool, length_scale);
  // An empty set keeps length scale 0 (its block has no sample).
  singles.erase(
      std::remove_if(singles.begin(), singles.end(), [&](int b) { return sets[b].y.empty(); }),
      singles.end());
  pool.parallelFor(static_cast<long long>(singles.size()), [&](long long k, int worker) {
    const BlockSet& set = sets[singles[k]];
    LocalGp& local = workspaces[worker].gp;
    local.setData(set.az.data(), set.el.data(), set.y.data(), static_cast<int>(set.y.size()));
    length_scale[singles[k]] = local.searchLengthScale();
  });
  return length_scale;
}

}  // namespace

int predictTiledLocalGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, double shift, ThreadPool& pool,
                        PixelPredictions& out) {
  return predictTiledLocalGp(samples, shiftedTargets(samples, shift), angles, params,
                             PriorMean{shift}, pool, out);
}

int predictTiledLocalGp(const std::vector<AngularSample>& samples,
                        const std::vector<double>& targets, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, const PriorMean& prior,
                        ThreadPool& pool, PixelPredictions& out, PredictionPrecision precision) {
  const LocalGpParams& gp = params.gp;
  const double shift = prior.constant;
  fillPredictions(angles, static_cast<float>(shift), static_cast<float>(gp.priorVariance()), pool,
                  out);
  if (samples.empty()) return 0;
  // Bins of half the radius: queries of radius + half tile diagonal then scan ~2/3 less area
  // outside the circle than radius-sized bins would.
  const AngularBins bins(samples, 0.5 * params.radius_deg);

  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  const int tile = params.approx_tile;
  const int tiles_x = (cols + tile - 1) / tile, tiles_y = (rows + tile - 1) / tile;
  const int blocks_x = (tiles_x + kSearchBlock - 1) / kSearchBlock;
  const int blocks_y = (tiles_y + kSearchBlock - 1) / kSearchBlock;
  const float radius_sq = static_cast<float>(params.radius_deg * params.radius_deg);
  PerWorker<TileWorkspace> workspaces(pool.size(), TileWorkspace(gp));

  // 1. One length-scale search per block of tiles, on the samples nearest to the block centre.
  // The blocks' sets are gathered first so that sets of equal size share one batched search, one
  // set per SIMD lane (each lane computes exactly what a lone search would: same result).
  const long long block_count = static_cast<long long>(blocks_x) * blocks_y;
  std::vector<BlockSet> block_sets(static_cast<std::size_t>(block_count));
  const int block_px = tile * kSearchBlock;
  pool.parallelFor(block_count, [&](long long b, int worker) {
    TileWorkspace& ws = workspaces[worker];
    const int r0 = static_cast<int>(b / blocks_x) * block_px;
    const int c0 = static_cast<int>(b % blocks_x) * block_px;
    const TileGeometry geometry = tileGeometry(angles, r0, std::min(rows, r0 + block_px), c0,
                                               std::min(cols, c0 + block_px), params.radius_deg);
    const int n = loadNearestSamples(samples, targets, bins, geometry, params.max_neighbors, ws);
    block_sets[b] = {ws.az, ws.el, ws.y};
    block_sets[b].az.resize(n);
    block_sets[b].el.resize(n);
    block_sets[b].y.resize(n);
  });
  const std::vector<double> block_length_scale =
      searchBlockLengthScales(block_sets, gp, precision, pool, workspaces);

  // 2. Per tile: its own nearest samples, one factorisation, predictions for its pixels.
  std::vector<std::uint8_t> solved(std::size_t(tiles_x) * tiles_y, 0);
  pool.parallelFor(static_cast<long long>(tiles_x) * tiles_y, [&](long long t, int worker) {
    TileWorkspace& ws = workspaces[worker];
    const int ty = static_cast<int>(t / tiles_x), tx = static_cast<int>(t % tiles_x);
    const double length_scale =
        block_length_scale[std::size_t(ty / kSearchBlock) * blocks_x + tx / kSearchBlock];
    if (length_scale <= 0.0) return;  // no sample anywhere near the block
    const int r0 = ty * tile, c0 = tx * tile;
    const TileGeometry geometry = tileGeometry(angles, r0, std::min(rows, r0 + tile), c0,
                                               std::min(cols, c0 + tile), params.radius_deg);
    const int n = loadNearestSamples(samples, targets, bins, geometry, params.max_neighbors, ws);
    if (n == 0) return;
    ws.gp.setData(ws.az.data(), ws.el.data(), ws.y.data(), n);
    if (!ws.gp.posterior(length_scale, ws.factor, ws.beta)) return;
    solved[t] = 1;
    // The whole tile in one call: long pixel blocks vectorise better than tile rows.
    const int width = geometry.c1 - geometry.c0, height = geometry.r1 - geometry.r0;
    const int pixels = width * height;
    ws.pixel_az.resize(pixels);
    ws.pixel_el.resize(pixels);
    for (int r = 0; r < height; ++r) {
      std::copy_n(angles.azimuthRow(geometry.r0 + r) + c0, width, ws.pixel_az.data() + r * width);
      std::copy_n(angles.elevationRow(geometry.r0 + r) + c0, width, ws.pixel_el.data() + r * width);
    }
    ws.mean.resize(pixels);
    ws.var.resize(pixels);
    ws.min_d2.resize(pixels);
    minSquaredDistance(ws.pixel_az.data(), ws.pixel_el.data(), pixels, ws, n, ws.min_d2.data());
    predictFromFactor(ws.factor.data(), ws.beta.data(), ws.az.data(), ws.el.data(), n, length_scale,
                      gp, ws.pixel_az.data(), ws.pixel_el.data(), pixels, shift, ws.mean.data(),
                      ws.var.data(), precision);
    for (int r = 0; r < height; ++r) {
      const std::size_t row_start = std::size_t(geometry.r0 + r) * cols + c0;
      for (int c = 0; c < width; ++c) {
        const int p = r * width + c;
        if (!(ws.min_d2[p] <= radius_sq)) continue;  // no sample within the radius: prior
        out.mean[row_start + c] = ws.mean[p];
        out.variance[row_start + c] = ws.var[p];
      }
    }
  });
  int count = 0;
  for (auto s : solved)
    count += s;
  return count;
}

double meanSamplesWithinRadius(const std::vector<AngularSample>& samples,
                               const PixelAngleGrid& angles, const DepthCompletionParams& params) {
  const ImageSize& image = angles.grid().image;
  std::vector<AngularSample> in_view;
  for (const AngularSample& s : usableSamples(samples)) {
    double u = 0, v = 0;
    if (angularToPixel(angles.intrinsics(), s.azimuth_deg, s.elevation_deg, &u, &v) && u >= 0.0 &&
        v >= 0.0 && u < image.width && v < image.height) {
      in_view.push_back(s);
    }
  }
  if (in_view.empty()) return 0.0;
  const double radius = params.radius_deg;
  const AngularBins bins(in_view, radius);
  std::size_t pairs = 0;
  for (const AngularSample& s : in_view) {
    bins.query(s.azimuth_deg, s.elevation_deg, radius, [&](int i) {
      const double da = in_view[i].azimuth_deg - s.azimuth_deg;
      const double de = in_view[i].elevation_deg - s.elevation_deg;
      pairs += da * da + de * de <= radius * radius;
    });
  }
  return double(pairs) / double(in_view.size());
}

}  // namespace multimodal_nvs
