#include "multimodal_nvs/core/depth/models/ground_gp_model.hpp"

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
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <type_traits>

#include "multimodal_nvs/core/common/per_worker.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/vectorisable_math.hpp"
#include "multimodal_nvs/core/depth/angular_bins.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/angular_triangulation.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/models/local_gp_model.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/models/tiled_local_gp_model.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/region_nearest.hpp"
#include "multimodal_nvs/core/depth/surface_colours.hpp"

namespace multimodal_nvs {
namespace {
// A return within this fraction of the ground depth along its ray counts as a ground return.
constexpr double kGroundMargin = 0.1;
// The residual GP's length-scale search stops at a bracket this wide (degrees) instead of the
// reference's 1e-3: the golden-section sequence is the same, it ends after ~11 likelihood
// evaluations instead of ~20, and a length scale within 0.05 deg of the optimum (over 0.1-10 deg)
// changes the residual's posterior by far less than its own standard deviation.
constexpr double kResidualLengthScaleToleranceDeg = 0.05;

// The prior: min(ground depth, surface depth), the far value where neither bounds the depth.
// vectorisable_math.hpp's spellings: GCC does not vectorise the full-image pass with the std ones.
inline float priorDepth(float ground, float nearest, float far) {
  const float prior = minOf(ground, nearest);
  return isFiniteVectorisable(prior) ? prior : far;
}

/// Each grid column's normalised image x, (c - cx) / fx, of an undistorted camera: the x of
/// plane.depthAlong(x, y) in the full-image prior passes.
std::vector<double> pinholeColumnX(const PixelAngleGrid& angles) {
  const PinholeIntrinsics& k = angles.intrinsics();
  const StrideGrid& grid = angles.grid();
  std::vector<double> column_x(grid.cols());
  for (int c = 0; c < grid.cols(); ++c)
    column_x[c] = (double(c) * grid.stride - k.cx) / k.fx;
  return column_x;
}
}  // namespace

void predictGroundGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const NeighbourSets* sets, const DepthCompletionParams& params,
                     const GroundPlane& plane, double median_depth, ThreadPool& pool,
                     PixelPredictions& out, const cv::Mat& image) {
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
  // The prior's uncertainty grows with the distance to the nearest return of any kind, found in
  // the same lattice pass. The lattice stays coarse: the prior
  //   prior = min(ground depth, surface depth), the far value where neither bounds the depth,
  // is only formed in the final full-image pass (and at the samples), so no full-resolution prior
  // is written, copied and read back.
  std::optional<SurfaceColours> colours;
  if (g.surface_colour_sigma > 0.0 && !image.empty())
    colours.emplace(image, angles.grid().image, g.surface_colour_sigma);
  const NearestSurfaceRows surface =
      nearestSurfaceRows(objects, angles, g.surface_k, g.surface_rank, step, pool,
                         objects.size() == samples.size() ? nullptr : &samples,
                         SurfacePriorImage{colours ? &*colours : nullptr, g.surface_colour_walls,
                                           params.guided.far_depth, g.surface_colour_fill_deg});
  const PinholeIntrinsics& k = angles.intrinsics();
  const StrideGrid& grid = angles.grid();
  const int rows = grid.rows(), cols = grid.cols();
  const float farf = static_cast<float>(far);
  // The ground depth of a pixel ray is -h / (up . d), with x = X/Z per column.
  const std::vector<double> column_x = pinholeColumnX(angles);

  // A distorted camera's rays are not separable into a column's x and a row's y: its pass reads
  // each pixel's ray from the grid's table (a separate instantiation, so that the pinhole pass
  // keeps its arithmetic and vectorisation).
  const auto row_pass = [&](long long r, auto distorted) {
    const double y = (r * grid.stride - k.cy) / k.fy;
    const NearestSurfaceRows::RowWeights w = surface.row(static_cast<int>(r));
    // Restrict-qualified so that the compiler vectorises the pass.
    float* __restrict const mean_row = out.mean.data() + r * cols;
    float* __restrict const variance_row = out.variance.data() + r * cols;
    const float* __restrict const depth_lo = w.depth_lo;
    const float* __restrict const depth_hi = w.depth_hi;
    const float* __restrict const distance_lo = w.distance_lo;
    const float* __restrict const distance_hi = w.distance_hi;
    const double* __restrict const xs = column_x.data();
    // Loop invariants in locals: loads through `plane` or `g` inside the loop would stop
    // vectorisation (they might alias the stores).
    const bool has_depth = surface.has_depth;
    const double up_x = plane.up.x(), up_y = plane.up.y() * y, up_z = plane.up.z();
    const double up_y_unit = plane.up.y();
    const double height = plane.height;
    const double rel = g.relative_sigma, rel_per_deg = g.relative_sigma_per_deg;
    const float t = w.t, far_value = farf;
    for (int c = 0; c < cols; ++c) {
      // plane.depthAlong(xs[c], y) and the surface depth as selects, not branches (the same
      // arithmetic), so that the loop vectorises (with -fno-trapping-math, CMakeLists.txt).
      double descent = up_x * xs[c] + up_y + up_z;
      if constexpr (decltype(distorted)::value) {
        const Eigen::Vector2d ray = angles.normalisedRay(static_cast<int>(r), c);
        descent = up_x * ray.x() + up_y_unit * ray.y() + up_z;
      }
      const double ground_depth = -height / descent;
      const float ground = static_cast<float>(descent < 0.0 ? ground_depth : INFINITY);
      const float lerped = NearestSurfaceRows::lerp(depth_lo[c], depth_hi[c], t);
      const float nearest = has_depth ? lerped : INFINITY;
      const float prior = priorDepth(ground, nearest, far_value);
      const float support_distance = NearestSurfaceRows::lerp(distance_lo[c], distance_hi[c], t);
      // A depth is positive: the residual GP must not push a near prior through the camera.
      const float mean = std::max(mean_row[c] + prior, 0.1f);
      const float sigma = mean * static_cast<float>(rel + rel_per_deg * support_distance);
      mean_row[c] = mean;
      variance_row[c] += sigma * sigma;
    }
  };
  const auto finish_row = [&](long long r) {
    if (angles.distorted()) {
      row_pass(r, std::true_type{});
    } else {
      row_pass(r, std::false_type{});
    }
  };
  if (g.residual_amplitude > 0.0) {
    // The prior at each sample's own direction: ground capped by the prior of the nearest grid
    // pixel (the lattice is only known on the grid).
    std::vector<double> residual(samples.size(), 0.0);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const Eigen::Vector2d ray =
          normalisedFromAngles(samples[i].azimuth_deg, samples[i].elevation_deg);
      double pu = k.fx * ray.x() + k.cx, pv = k.fy * ray.y() + k.cy;
      if (angles.distorted() &&
          !angularToPixel(k, samples[i].azimuth_deg, samples[i].elevation_deg, &pu, &pv)) {
        pu = pv = -1e9;  // past the lens model's range: off the grid
      }
      const int c = static_cast<int>(std::lround(pu / grid.stride));
      const int r = static_cast<int>(std::lround(pv / grid.stride));
      double at_sample = plane.depthAlong(ray.x(), ray.y());
      if (r >= 0 && c >= 0 && r < rows && c < cols) {
        const double y = (r * grid.stride - k.cy) / k.fy;
        const Eigen::Vector2d pixel_ray =
            angles.distorted() ? angles.normalisedRay(r, c) : Eigen::Vector2d(column_x[c], y);
        const float ground = static_cast<float>(plane.depthAlong(pixel_ray.x(), pixel_ray.y()));
        at_sample = std::min<double>(at_sample, priorDepth(ground, surface.depth(r, c), farf));
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
    residual_params.gp.tolerance = std::max(params.gp.tolerance, kResidualLengthScaleToleranceDeg);
    // The GP around a zero mean: out.mean is the residual's posterior mean (0 without a set); the
    // prior is added below.
    // Single precision in the length-scale search's likelihood and the per-pixel step (exact
    // sets and tiles alike): this model keeps no parity with the reference, and the residual GP's
    // small amplitude keeps its kernels well conditioned.
    if (sets != nullptr) {
      // The prior pass runs on each row as soon as the GP has written it (in cache).
      predictLocalGp(samples, residual, angles, *sets, residual_params, PriorMean{0.0}, pool, out,
                     PredictionPrecision::kSingle, finish_row);
      return;
    } else {
      predictTiledLocalGp(samples, residual, angles, residual_params, PriorMean{0.0}, pool, out,
                          PredictionPrecision::kSingle);
    }
  } else {
    fillPredictions(angles, 0.0f, 0.0f, pool, out);
  }
  pool.parallelFor(
      rows, [&](long long r, int) { finish_row(r); }, 16);
}

// ---------------------------------------------------------------------------------------------
// Dense input (LiDAR). With a sample every few tenths of a degree the local GP has hundreds of
// samples per neighbourhood and its residual around any interpolating prior is zero at every
// sample, so what matters is the interpolant itself. Two physical facts shape it:
// - on a plane (the road, a wall, the side of a car) inverse depth is an affine function of the
//   normalised image coordinates, so barycentric interpolation of 1/z is exact there up to the
//   angular (not normalised) barycentric weights, a second-order difference in the triangle's
//   size, while the `linear` baseline's interpolation of z is biased (z = h / y on the road is
//   convex);
// - across an occlusion edge a blend of the two depths lies on neither surface; a pixel there
//   belongs to one of them, and under an absolute error the best guess is the more probable one
//   rather than a blend.
// Two vertices of a triangle are on one surface when both are ground returns (the ground plane
// of the prior) or their depths differ by at most dense_edge_ratio. Inside a surface the pixel
// interpolates 1/z over the three vertices; in a triangle that spans an edge, its surface is the
// vertex depth best supported by its surface_k nearest samples, and it interpolates 1/z over the
// vertices on that surface, except on the ground, which continues along the plane up to the object
// that ends it (groundAcrossEdge). Pixels outside the triangulation get the
// sparse mode's prior (nearest sample capped by the ground) and its distance-inflated variance.
namespace {

// A gap in the triangulation, as in the sparse mode: lattice step of the nearest-sample fallback.
constexpr int kFallbackStepPx = 16;
// A sample at the pixel's own direction must not take infinite weight in the edge vote:
// (0.01 deg)^2, far below any sample spacing.
constexpr double kVoteDistanceFloorDeg2 = 1e-4;
// A vote whose winning surface has this many times the support of every other surface is reused
// for this many following pixels of the same triangle row (see the vote below).
constexpr double kVoteDecisiveRatio = 4.0;
constexpr int kVoteReusePixels = 3;
/// The last vote of a rasterising thread.
struct VoteMemory {
  unsigned long long frame = 0;  // of this call (a triangle's address may recur in another)
  const AngularTriangle* triangle = nullptr;
  std::size_t pixel = 0;
  int winner = 0;
  int reuses_left = 0;
};
// Bin side of the bins that gather the vote's candidates (affects only speed): a gather disc is
// ~1 deg wide on a full LiDAR scan (returns ~0.1-0.4 deg apart), so it walks a few dozen bins.
// One int per bin: a 360 x 40 deg sweep takes 58k bins.
constexpr double kVoteBinDeg = 0.5;
// The vote's regions: tiles of 8 x 8 grid pixels, ~0.27 deg square on a VoD-like camera. One
// gather serves every edge pixel of the tile, whichever triangle it lies in (per triangle, or per
// tile of each large triangle, a tile was gathered again for each triangle crossing it). 4 x 16,
// 8 x 16, 16 x 16 and 16 x 8 tiles were as fast or up to 10 % slower on VoD 00549.
constexpr int kTileRows = 8;
constexpr int kTileCols = 8;

/// A gathered tile of vote candidates and which tile of which call it is.
struct VoteRegion {
  unsigned long long frame = 0;  // of this call
  int tile_row = -1;
  RegionNearest candidates;
};

/// Gathers into `region` the samples that can be among the k nearest of any point within `extent`
/// of (az, el). The first bound on the centre's k-th distance is the previous region's (regions of
/// one thread are neighbours), a little widened so that one gather usually suffices.
void gatherVoteRegion(double az, double el, double extent, int k, const AngularBins& bins,
                      RegionNearest& region) {
  constexpr double kGuessWidening = 1.25;
  thread_local double guess = 0.0;
  guess = kGuessWidening *
          region.gatherAround(bins, az, el, extent, static_cast<std::size_t>(k), guess);
}

/// The k samples nearest to the pixel (az, el), as AngularBins::nearest() gives them. The edge
/// vote asks for them at most pixels of an edge triangle, so each rasterising thread gathers the
/// samples that can be among any of a tile's pixels' k nearest once per tile (RegionNearest) and
/// answers each pixel from those: one bin walk per pixel was the largest cost of the dense mode.
void voteNeighbours(unsigned long long frame, std::size_t pixel, float az, float el, int k,
                    const AngularBins& bins, const PixelAngleGrid& angles,
                    std::vector<std::pair<double, int>>& nearest) {
  // Slots by (tile row modulo 2, tile column): a band of the rasteriser (16 rows) holds two tile
  // rows, and its triangles alternate between them row by row.
  thread_local std::vector<VoteRegion> tiles;
  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  const int r = static_cast<int>(pixel / static_cast<std::size_t>(cols));
  const int c = static_cast<int>(pixel % static_cast<std::size_t>(cols));
  const int tile_cols = (cols + kTileCols - 1) / kTileCols;
  tiles.resize(2 * static_cast<std::size_t>(tile_cols));
  const int tile_row = r / kTileRows;
  VoteRegion& tile = tiles[std::size_t(tile_row % 2) * tile_cols + c / kTileCols];
  if (tile.frame != frame || tile.tile_row != tile_row) {
    tile.frame = frame;
    tile.tile_row = tile_row;
    // The tile's angular box from its pixels' own angles (any camera model).
    const int r0 = tile_row * kTileRows, r1 = std::min(rows, r0 + kTileRows);
    const int c0 = c / kTileCols * kTileCols, c1 = std::min(cols, c0 + kTileCols);
    float az0 = az, az1 = az, el0 = el, el1 = el;
    for (int rr = r0; rr < r1; ++rr) {
      const float* row_az = angles.azimuthRow(rr);
      const float* row_el = angles.elevationRow(rr);
      for (int cc = c0; cc < c1; ++cc) {
        // Written so that a NaN angle (beyond a lens model's range) is skipped.
        if (row_az[cc] < az0) az0 = row_az[cc];
        if (row_az[cc] > az1) az1 = row_az[cc];
        if (row_el[cc] < el0) el0 = row_el[cc];
        if (row_el[cc] > el1) el1 = row_el[cc];
      }
    }
    const double half_az = 0.5 * (double(az1) - az0), half_el = 0.5 * (double(el1) - el0);
    gatherVoteRegion(az0 + half_az, el0 + half_el, std::hypot(half_az, half_el), k, bins,
                     tile.candidates);
  }
  tile.candidates.nearest(az, el, static_cast<std::size_t>(k), nearest);
}

// Half-width of a column's band of returns for the upward extension, in mean sample spacings.
constexpr double kColumnBandSpacings = 0.5;
// A triangle with an edge longer than this many mean sample spacings bridges a region without
// returns; above a column's topmost return the column extension replaces its interpolation.
constexpr double kBridgeSpacings = 20.0;

/// Two depths of one surface: the larger at most `ratio` times the smaller.
inline bool depthsWithinRatio(double a, double b, double ratio) {
  return std::max(a, b) <= ratio * std::min(a, b);
}

/// The camera image in the occlusion vote (ground.dense_vote_colour_sigma): a return whose pixel
/// looks like the pixel counts more for its surface. Between the scan lines of a sparse LiDAR (16
/// or 32 beams, or every 4th return of any) the nearest returns of a pixel on a car may be the
/// road's or the wall's behind it, and the angles alone cannot tell; the image's edge can. Next to
/// returns the angles decide: a return's pixel may lie a few pixels off its surface (the LiDAR sees
/// the scene from elsewhere; the calibration). So the colours have no say within half of
/// dense_vote_colour_px image pixels of the nearest return, and a say growing linearly to full at
/// dense_vote_colour_px. On a 64-beam LiDAR that leaves them ~3 % of the vote's queries (VoD
/// 00549), so the colours are looked up where asked, not for every pixel and return up front.
class VoteColours {
 public:
  /// A pixel's colour and the colours' say (0..1) in its vote.
  struct Pixel {
    CellColour colour{NAN, NAN, NAN};
    double say = 0.0;
  };

  /// `call`: the number of this call of the dense mode (its vote memories' `frame`), which tells
  /// the threads' colour caches of this call from those of earlier ones.
  VoteColours(unsigned long long call, const cv::Mat& image, const PixelAngleGrid& angles,
              const std::vector<AngularSample>& samples, const GroundPriorParams& g)
      : call_(call),
        colours_(image, angles.grid().image, g.dense_vote_colour_sigma),
        angles_(angles),
        samples_(samples),
        // Degrees per image pixel at the image centre: the say's distances in degrees.
        full_say_deg_(g.dense_vote_colour_px * 180.0 / M_PI / angles.intrinsics().fx),
        no_say_deg2_(0.25 * full_say_deg_ * full_say_deg_) {}

  /// The colours' say in the vote of a pixel whose nearest sample lies `distance2` (squared
  /// degrees) away. Most pixels of a dense LiDAR lie nearer than half the distance: they are told
  /// without a square root.
  double say(double distance2) const {
    if (!(distance2 > no_say_deg2_)) return 0.0;
    if (!(full_say_deg_ > 0.0)) return 1.0;
    return std::min(1.0, 2.0 * std::sqrt(distance2) / full_say_deg_ - 1.0);
  }

  /// Grid pixel `pixel`'s colour (its cell's).
  CellColour pixelColour(std::size_t pixel, int cols) const {
    const int stride = angles_.grid().stride;
    const int u = static_cast<int>(pixel % static_cast<std::size_t>(cols)) * stride;
    const int v = static_cast<int>(pixel / static_cast<std::size_t>(cols)) * stride;
    return colours_.at(u, v);
  }

  /// Sample `sample`'s factor in the vote of a pixel: 1 without a say, the colour weight with a
  /// full one.
  double weight(const Pixel& pixel, int sample) const {
    const double w = colours_.weight(pixel.colour, sampleColour(sample));
    return 1.0 - pixel.say * (1.0 - w);
  }

 private:
  /// A sample's colour, computed once per thread and call where first asked.
  const CellColour& sampleColour(int sample) const {
    struct Cache {
      unsigned long long owner = 0;  // call_ of the VoteColours that filled it
      std::vector<std::uint8_t> known;
      std::vector<CellColour> colour;
    };
    thread_local Cache cache;
    if (cache.owner != call_) {
      cache.owner = call_;
      cache.known.assign(samples_.size(), 0);
      cache.colour.resize(samples_.size());
    }
    if (!cache.known[sample]) {
      cache.colour[sample] = colours_.atSample(samples_[sample], angles_);
      cache.known[sample] = 1;
    }
    return cache.colour[sample];
  }

  unsigned long long call_;
  SurfaceColours colours_;
  const PixelAngleGrid& angles_;
  const std::vector<AngularSample>& samples_;
  double full_say_deg_;
  double no_say_deg2_;  // (full_say_deg_ / 2)^2
};

/// The edge vote's supports again with the colours (`say` > 0), where they can change it: where
/// two of the pixel's nearest samples support different vertices (elsewhere the colours would
/// scale every support alike). `support` holds the votes by angle alone and is replaced.
void colourVote(const VoteColours& colours, double say, std::size_t pixel, int cols,
                const std::vector<std::pair<double, int>>& nearest,
                const std::vector<AngularSample>& usable, const AngularTriangle& t, double ratio,
                double support[3]) {
  const auto supported = [&](int sample) {
    unsigned bits = 0;  // bit i: vertex i
    for (int i = 0; i < 3; ++i)
      bits |= unsigned(depthsWithinRatio(usable[sample].depth, t.z[i], ratio)) << i;
    return bits;
  };
  unsigned seen = 0;
  bool split = false;
  for (const auto& nn : nearest) {
    const unsigned bits = supported(nn.second);
    split |= bits != 0 && seen != 0 && bits != seen;
    if (bits != 0) seen = bits;
  }
  if (!split) return;
  const VoteColours::Pixel look{colours.pixelColour(pixel, cols), say};
  support[0] = support[1] = support[2] = 0.0;
  for (const auto& nn : nearest) {
    const double weight = colours.weight(look, nn.second) / (nn.first + kVoteDistanceFloorDeg2);
    const unsigned bits = supported(nn.second);
    for (int i = 0; i < 3; ++i) {
      if (bits >> i & 1) support[i] += weight;
    }
  }
}

/// The vertex of `t` nearest to (az, el) in the angular plane (the first of a tie).
int nearestVertex(const AngularTriangle& t, float az, float el) {
  int j = 0;
  double best = -1.0;
  for (int i = 0; i < 3; ++i) {
    const double d2 = (az - t.az[i]) * (az - t.az[i]) + (el - t.el[i]) * (el - t.el[i]);
    if (best < 0.0 || d2 < best) {
      best = d2;
      j = i;
    }
  }
  return j;
}

/// rasterizeSurfaceRow()'s per-thread buffers of a box row's values.
struct SurfaceRowScratch {
  std::vector<float> mean, variance;
};

struct DenseVertexInfo {
  bool ground[3];
  /// A ground vertex's depth over the plane's depth along its ray (near 1: how far the local road
  /// lies off the estimated plane).
  float plane_ratio[3];
  /// same[a][b]: vertices a and b lie on one surface (both ground returns, or depths within
  /// dense_edge_ratio); per triangle, so that the rasteriser does not re-derive it per pixel.
  bool same[3][3];
  bool edge;  ///< some pair of vertices lies on different surfaces
  float longest_edge_deg;
};

// A triangle whose vertex depths lie more than dense_edge_ratio apart is one surface all the same
// when it and the three triangles beside it lie on one plane: inverse depth is affine in the
// normalised image coordinates on a plane, so the six vertices fit w = a + b x + c y, each within
// kOnePlaneTolerance of its own w. What it catches: a facade seen from far along a street, whose
// returns along a sparse LiDAR's scan line (16 or 32 beams, or every 4th return) lie 10-30 % apart
// in depth; as an occlusion edge the vote gave each of its pixels one vertex's depth, a wedge of
// error metres deep, where interpolating 1/z is exact. A step between two surfaces (a pole before
// a facade, a car before the road) puts the vertices of both sides off any one plane; the
// triangle's own three vertices alone always span one, hence the neighbours. 1 %: depths of one
// plane to within a few centimetres at 5 m (a LiDAR's range noise), and no looser, since the
// novel views lost coverage at 3 % (README, "Edges on one plane").
constexpr double kOnePlaneTolerance = 0.01;
// Six points on or near one line (a sliver along the top scan line, whose neighbours lie on the
// same line) fit a plane whatever their depths: the points must spread across the image in both
// directions, the smaller principal axis of their (x, y) at least this share of the larger.
constexpr double kOnePlaneMinSpread = 0.2;

/// Whether triangle `t` and the vertices `m` across its edges lie on one plane (see above); false
/// at the hull (a neighbour missing).
bool onOnePlane(const AngularTriangle& t, const TriangleMirrors& m) {
  double x[6], y[6], w[6];
  for (int i = 0; i < 6; ++i) {
    const double z = i < 3 ? t.z[i] : m.vertex[i - 3].depth;
    if (!(z > 0.0)) return false;
    const Eigen::Vector2d ray =
        i < 3 ? normalisedFromAngles(t.az[i], t.el[i])
              : normalisedFromAngles(m.vertex[i - 3].azimuth_deg, m.vertex[i - 3].elevation_deg);
    x[i] = ray.x();
    y[i] = ray.y();
    w[i] = 1.0 / z;
  }
  // The least-squares fit through the normal equations of the centred points: the mean of w, and
  // the slopes from the 2x2 scatter of (x, y), whose eigenvalues also give the spread.
  double mx = 0.0, my = 0.0, mw = 0.0;
  for (int i = 0; i < 6; ++i) {
    mx += x[i];
    my += y[i];
    mw += w[i];
  }
  mx /= 6.0;
  my /= 6.0;
  mw /= 6.0;
  double sxx = 0.0, syy = 0.0, sxy = 0.0, sxw = 0.0, syw = 0.0;
  for (int i = 0; i < 6; ++i) {
    const double dx = x[i] - mx, dy = y[i] - my, dw = w[i] - mw;
    sxx += dx * dx;
    syy += dy * dy;
    sxy += dx * dy;
    sxw += dx * dw;
    syw += dy * dw;
  }
  const double half_trace = 0.5 * (sxx + syy);
  const double root = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  const double minor = half_trace - root, major = half_trace + root;
  if (!(major > 0.0 && minor >= kOnePlaneMinSpread * kOnePlaneMinSpread * major)) return false;
  const double det = sxx * syy - sxy * sxy;
  const double b = (sxw * syy - syw * sxy) / det, c = (syw * sxx - sxw * sxy) / det;
  for (int i = 0; i < 6; ++i) {
    const double fitted = mw + b * (x[i] - mx) + c * (y[i] - my);
    if (!(std::abs(fitted - w[i]) <= kOnePlaneTolerance * w[i])) return false;
  }
  return true;
}

/// The ground plane's depth along a triangle vertex's direction, remembered for the directions
/// seen last (direct-mapped on the angles' bits, so a hit returns the very bits a computation
/// would): a vertex belongs to ~6 triangles, mostly near one another in the triangulation's
/// order, and its two tangents and cosine were most of the triangles' per-vertex pass.
class PlaneDepthCache {
 public:
  double operator()(const GroundPlane& plane, double az, double el) {
    std::uint64_t az_bits = 0, el_bits = 0;
    std::memcpy(&az_bits, &az, sizeof az);
    std::memcpy(&el_bits, &el, sizeof el);
    Entry& entry = entries_[((az_bits * 0x9E3779B97F4A7C15ull) ^ el_bits) >> (64 - kBits)];
    if (entry.filled && entry.az_bits == az_bits && entry.el_bits == el_bits) return entry.depth;
    const Eigen::Vector2d ray = normalisedFromAngles(az, el);
    entry = {az_bits, el_bits, plane.depthAlong(ray.x(), ray.y()), true};
    return entry.depth;
  }

 private:
  static constexpr int kBits = 10;
  struct Entry {
    std::uint64_t az_bits = 0, el_bits = 0;
    double depth = 0.0;
    bool filled = false;
  };
  std::vector<Entry> entries_ = std::vector<Entry>(std::size_t{1} << kBits);
};

/// The pixels of one box row of a triangle without an occlusion edge (one surface; most pixels of
/// a LiDAR frame): depth interpolated as inverse depth, variance from the surface's relative sigma
/// (`rel2`) plus the spread of the three depths. The same arithmetic as the per-pixel path of an
/// edge triangle whose pixel lies on the surface of all three vertices, bit for bit, but in two
/// loops: the row's span of pixels inside in whole blocks of vector arithmetic into `scratch`
/// (its blocks may reach past the box into the padding of `box`'s buffers), then a branch-free
/// store of those inside and not yet filled. Per pixel it divides four times, which
/// one at a time was most of the rasteriser's cost.
void rasterizeSurfaceRow(const AngularTriangle& t, float longest_edge_deg, double rel2,
                         const TriangleBoxRow& box, std::uint8_t* filled_row, float* mean_row,
                         float* variance_row, float* longest_row, SurfaceRowScratch& scratch) {
  const std::size_t padded = std::size_t(box.width) + kBarycentricBlock;
  if (scratch.mean.size() < padded) {
    scratch.mean.resize(padded);
    scratch.variance.resize(padded);
  }
  float* __restrict mean_out = scratch.mean.data();
  float* __restrict variance_out = scratch.variance.data();
  const double z0 = t.z[0], z1 = t.z[1], z2 = t.z[2];
  const double fallback_inverse = 1.0 / z0;  // no weight: the nearest vertex, 0 without an edge
  const BlockDoubles zero = BlockDoubles{} + 0.0;
  // Only the span from the first to the last pixel inside (on a VoD LiDAR frame a one-surface
  // triangle's box row is ~10 pixels wide with ~3 inside).
  int first = 0, last = box.width - 1;
  while (first <= last && !box.inside[first])
    ++first;
  while (last >= first && !box.inside[last])
    --last;
  for (int b = first; b <= last; b += kBarycentricBlock) {
    BlockDoubles l1, l2;
    loadBlock(box.l1s + b, l1);
    loadBlock(box.l2s + b, l2);
    const BlockDoubles l0 = 1.0 - l1 - l2;
    // std::max(0.0, l) spelled out, NaN to 0 as it does.
    const BlockDoubles a0 = 0.0 < l0 ? l0 : zero, a1 = 0.0 < l1 ? l1 : zero,
                       a2 = 0.0 < l2 ? l2 : zero;
    BlockDoubles weight = zero, inverse = zero;
    weight += a0;
    inverse += a0 / z0;
    weight += a1;
    inverse += a1 / z1;
    weight += a2;
    inverse += a2 / z2;
    const BlockMask none = ~(weight > 0.0);
    weight = none ? zero + 1.0 : weight;
    inverse = none ? zero + fallback_inverse : inverse;
    const BlockDoubles mean = weight / inverse;
    BlockDoubles spread = zero;
    spread += a0 * (z0 - mean) * (z0 - mean);
    spread += a1 * (z1 - mean) * (z1 - mean);
    spread += a2 * (z2 - mean) * (z2 - mean);
    const BlockFloats mean32 = __builtin_convertvector(mean, BlockFloats);
    const BlockFloats variance32 =
        __builtin_convertvector(rel2 * mean * mean + spread, BlockFloats);
    std::memcpy(mean_out + b, &mean32, sizeof mean32);
    std::memcpy(variance_out + b, &variance32, sizeof variance32);
  }
  for (int i = first; i <= last; ++i) {
    const int c = box.col0 + i;
    const bool write = box.inside[i] && !filled_row[c];
    mean_row[c] = write ? mean_out[i] : mean_row[c];
    variance_row[c] = write ? variance_out[i] : variance_row[c];
    longest_row[c] = write ? longest_edge_deg : longest_row[c];
    filled_row[c] = filled_row[c] | std::uint8_t(write);
  }
}

/// A pixel of an edge triangle that the vote put on the ground. The road goes on between two scan
/// lines until something stands on it, so the pixel's depth is the plane's along its ray, scaled
/// by the ground vertices' ratio to the plane (how far the local road lies off the estimated
/// plane), and capped where the road ends: at the nearest non-ground vertex's depth (the object the
/// road runs up to) or, where that object is nearer than the road's own vertices (the road seen
/// past it), at their interpolation, the depth the pixel had without this step. Interpolating the
/// ground vertices alone holds one scan line's depth across the gap to the next: with scan lines
/// degrees apart (a 32-beam LiDAR, every 4th of its rings) that is metres short of the road.
/// Above the horizon (no ground along the ray) `interpolated` stands.
double groundAcrossEdge(const AngularTriangle& t, const DenseVertexInfo& v, const double l[3],
                        std::size_t pixel, int cols, const PixelAngleGrid& angles,
                        const GroundPlane& plane, double interpolated) {
  double weight = 0.0, ratio = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (!v.ground[i]) continue;
    weight += l[i];
    ratio += l[i] * v.plane_ratio[i];
  }
  ratio = weight > 0.0 ? ratio / weight : 1.0;
  const int r = static_cast<int>(pixel / static_cast<std::size_t>(cols));
  const int c = static_cast<int>(pixel % static_cast<std::size_t>(cols));
  const Eigen::Vector2d ray = angles.normalisedRay(r, c);
  const double along = ratio * plane.depthAlong(ray.x(), ray.y());
  if (!std::isfinite(along)) return interpolated;
  double nearest_object = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (!v.ground[i] && (nearest_object == 0.0 || t.z[i] < nearest_object)) nearest_object = t.z[i];
  }
  return std::min(along, std::max(nearest_object, interpolated));
}

/// What the gap pass needs of the ground plane and the prior's parameters, as plain values.
struct GapRowConstants {
  double up_x, up_y, up_z, height;
  float far;
  double relative_sigma, relative_sigma_per_deg;
};

/// The gap pass (the sparse mode's prior: nearest return capped by the ground, the far value where
/// neither bounds the depth) on one row of a pinhole camera, for the pixels not filled: the
/// arithmetic of groundPriorDepthAt() and the per-pixel pass it replaces, written so that the row
/// vectorises (selects for branches, -fno-trapping-math).
__attribute__((noinline)) void fillGapRow(const GapRowConstants& k, const double* __restrict xs,
                                          double y, const NearestSurfaceRows::RowWeights& w,
                                          bool has_depth, int cols,
                                          const std::uint8_t* __restrict filled,
                                          float* __restrict mean_out,
                                          float* __restrict variance_out) {
  const double up_x = k.up_x, up_y = k.up_y, up_z = k.up_z, height = k.height;
  const double rel = k.relative_sigma, rel_per_deg = k.relative_sigma_per_deg;
  const float far = k.far, t = w.t;
  const float* __restrict const depth_lo = w.depth_lo;
  const float* __restrict const depth_hi = w.depth_hi;
  const float* __restrict const distance_lo = w.distance_lo;
  const float* __restrict const distance_hi = w.distance_hi;
  thread_local std::vector<float> gap_mean_row, gap_variance_row;
  gap_mean_row.resize(cols);
  gap_variance_row.resize(cols);
  float* __restrict const gap_mean = gap_mean_row.data();
  float* __restrict const gap_variance = gap_variance_row.data();
  for (int c = 0; c < cols; ++c) {
    const float lerped = NearestSurfaceRows::lerp(depth_lo[c], depth_hi[c], t);
    const float nearest_depth = has_depth ? lerped : INFINITY;
    const float distance_deg = NearestSurfaceRows::lerp(distance_lo[c], distance_hi[c], t);
    // groundPriorDepthAt() with an infinite far value: plane.depthAlong(x, y) as float.
    const double descent = up_x * xs[c] + up_y * y + up_z;
    const float ground = static_cast<float>(descent < 0.0 ? -height / descent : INFINITY);
    float mean = priorDepth(ground, nearest_depth, far);
    mean = mean < 0.1f ? 0.1f : mean;
    const float sigma = mean * static_cast<float>(rel + rel_per_deg * distance_deg);
    gap_mean[c] = mean;
    gap_variance[c] = sigma * sigma;
  }
  // Apart, so that the loop above has no byte-sized data (GCC 12 did not vectorise it with them).
  for (int c = 0; c < cols; ++c) {
    if (filled[c]) continue;
    mean_out[c] = gap_mean[c];
    variance_out[c] = gap_variance[c];
  }
}

// Above the highest ring (the triangulation's hull ends there, and its hull-edge triangles
// interpolate across whatever lies at the two ends). What the camera sees there is mostly
// vertical structure: facades, poles, trees, vehicles' sides. For a level camera a vertical line
// of the world lies on one image column at one camera depth z, so the best guess above the
// topmost return of a column is that return's depth (the column extension of ipbasic, here on
// the return itself rather than on a dilated image). Its uncertainty is the surface's own, growing
// with the angular distance above the return: the higher, the likelier the structure has ended.
// A column whose topmost return is on the ground has no structure to extend and keeps the
// nearest-sample prior.

/// What the column extension extends: each column's topmost return (grid row and depth), the
/// rows it extends down to (0: none) and the triangles' bridge length. It does not depend on the
/// triangulation, so it is found while the triangulation runs.
struct ColumnExtension {
  std::vector<double> top_v;
  std::vector<float> top_z;
  std::vector<int> extend_rows;
  double deg_per_px = 0.0, bridge_deg = 0.0;
};

ColumnExtension columnExtension(const std::vector<AngularSample>& usable,
                                const PixelAngleGrid& angles, const GroundPlane& plane,
                                ThreadPool& pool) {
  ColumnExtension e;
  const StrideGrid& grid = angles.grid();
  const PinholeIntrinsics& k = angles.intrinsics();
  const int rows = grid.rows(), cols = grid.cols();
  struct Projected {
    double u, v;  // grid coordinates
    float z;
  };
  // The returns that project into the grid's columns (or just beside them) and not below it. Two
  // tangents and a cosine per return were ~5 ms of serial work on a 360-degree HDL-64 sweep: the
  // returns are projected in chunks on the pool (kept in order), and those outside the columns'
  // azimuths are skipped before any tangent (azimuthWindow; the exact test below decides).
  const AzimuthWindow window = azimuthWindow(k, -1.0 * grid.stride, double(cols) * grid.stride);
  constexpr std::size_t kChunk = 8192;
  const std::size_t chunks = (usable.size() + kChunk - 1) / kChunk;
  std::vector<std::vector<Projected>> parts(chunks);
  pool.parallelFor(static_cast<long long>(chunks), [&](long long part, int) {
    const std::size_t begin = std::size_t(part) * kChunk;
    const std::size_t end = std::min(usable.size(), begin + kChunk);
    for (std::size_t i = begin; i < end; ++i) {
      const AngularSample& s = usable[i];
      if (!window.contains(s.azimuth_deg)) continue;
      double u = 0, v = 0;
      if (!angularToPixel(k, s.azimuth_deg, s.elevation_deg, &u, &v)) continue;
      u /= grid.stride;
      v /= grid.stride;
      if (u < -1.0 || u > cols || v > rows) continue;
      parts[part].push_back({u, v, s.depth});
    }
  });
  std::vector<Projected> projected;
  double v0 = INFINITY, v1 = -INFINITY;
  for (const std::vector<Projected>& part : parts) {
    for (const Projected& q : part) {
      projected.push_back(q);
      v0 = std::min(v0, q.v);
      v1 = std::max(v1, q.v);
    }
  }
  if (projected.empty()) return e;
  // A column's returns: those within half the mean sample spacing (grid pixels) of it, so that
  // each column sees about one return per ring and no neighbour's.
  const double spacing = std::sqrt(std::max(1.0, v1 - v0) * cols / double(projected.size()));
  const double band = kColumnBandSpacings * spacing;
  std::vector<double>& top_v = e.top_v;
  std::vector<float>& top_z = e.top_z;
  top_v.assign(cols, INFINITY);
  top_z.assign(cols, INFINITY);
  for (const Projected& q : projected) {
    const int c0 = std::max(0, static_cast<int>(std::ceil(q.u - band)));
    const int c1 = std::min(cols - 1, static_cast<int>(std::floor(q.u + band)));
    for (int c = c0; c <= c1; ++c) {
      // The topmost return; on a tie the nearer one (the first surface).
      if (q.v < top_v[c] || (q.v == top_v[c] && q.z < top_z[c])) {
        top_v[c] = q.v;
        top_z[c] = q.z;
      }
    }
  }
  // A column between two bands (the spacing is a mean): the nearest covered column's return.
  const std::vector<double> band_v = top_v;
  const std::vector<float> band_z = top_z;
  const int reach = static_cast<int>(std::ceil(spacing));
  for (int c = 0; c < cols; ++c) {
    for (int d = 1; d <= reach && !std::isfinite(top_z[c]); ++d) {
      for (const int n : {c - d, c + d}) {
        if (n >= 0 && n < cols && std::isfinite(band_z[n]) && !std::isfinite(top_z[c])) {
          top_v[c] = band_v[n];
          top_z[c] = band_z[n];
        }
      }
    }
  }
  e.deg_per_px = grid.stride * 180.0 / (M_PI * k.fy);
  e.bridge_deg = kBridgeSpacings * spacing * e.deg_per_px;
  // The rows each column extends down to (0: not extended; a ground return is not extended).
  std::vector<int>& extend_rows = e.extend_rows;
  extend_rows.assign(cols, 0);
  for (int c = 0; c < cols; ++c) {
    if (!std::isfinite(top_z[c]) || top_v[c] <= 0.0) continue;
    double x = (double(c) * grid.stride - k.cx) / k.fx;
    double y = (top_v[c] * grid.stride - k.cy) / k.fy;
    if (angles.distorted()) {
      const int top_row = std::clamp(static_cast<int>(std::lround(top_v[c])), 0, rows - 1);
      const Eigen::Vector2d ray = angles.normalisedRay(top_row, c);
      x = ray.x();
      y = ray.y();
    }
    if (top_z[c] >= (1.0 - kGroundMargin) * plane.depthAlong(x, y)) continue;  // ground
    extend_rows[c] = std::min(rows, static_cast<int>(std::ceil(top_v[c])));
  }
  return e;
}

struct ExtensionRowConstants {
  double bridge_deg, deg_per_px, dense_sigma, sigma_per_deg;
};

/// One row of the column extension: above its column's top return (r < extend_rows[c]) a pixel
/// takes that return's depth, and a std growing with the angle above it; inside the triangulation
/// its interpolation stands, unless the triangle bridges a region without returns (hull-edge
/// triangles above the top ring reach across to whatever return is highest nearby, a pole top or
/// a distant roof). Every pixel's values are computed and one kept (a select, not a branch);
/// restrict pointers, or GCC keeps the loop scalar.
void extendRow(const ExtensionRowConstants& k, int r, int cols, const int* __restrict extend_rows,
               const double* __restrict top_v, const float* __restrict top_z,
               const std::uint8_t* __restrict filled, const float* __restrict longest,
               float* __restrict mean, float* __restrict variance) {
  for (int c = 0; c < cols; ++c) {
    const bool keep = (r >= extend_rows[c]) | ((filled[c] != 0) & (longest[c] <= k.bridge_deg));
    const double above = (top_v[c] - r) * k.deg_per_px;
    const double sigma = top_z[c] * (k.dense_sigma + k.sigma_per_deg * above);
    const float extended_variance = static_cast<float>(sigma * sigma);
    mean[c] = keep ? mean[c] : top_z[c];
    variance[c] = keep ? variance[c] : extended_variance;
  }
}

void extendColumnsUpward(const ColumnExtension& e, const PixelAngleGrid& angles,
                         const std::vector<std::uint8_t>& filled, const std::vector<float>& longest,
                         const GroundPriorParams& g, ThreadPool& pool, PixelPredictions& out) {
  if (e.extend_rows.empty()) return;
  const int cols = angles.grid().cols();
  // Written row by row (a column at a time wrote one float per cache line), branch-free so that
  // the row vectorises; rows below every column's top return have nothing to extend.
  const ExtensionRowConstants constants{e.bridge_deg, e.deg_per_px, g.dense_relative_sigma,
                                        g.relative_sigma_per_deg};
  const int last_row = *std::max_element(e.extend_rows.begin(), e.extend_rows.end());
  pool.parallelFor(
      last_row,
      [&](long long r, int) {
        const std::size_t row = std::size_t(r) * cols;
        extendRow(constants, static_cast<int>(r), cols, e.extend_rows.data(), e.top_v.data(),
                  e.top_z.data(), filled.data() + row, longest.data() + row, out.mean.data() + row,
                  out.variance.data() + row);
      },
      16);
}

}  // namespace

double meanSampleSpacingDeg(const std::vector<AngularSample>& samples,
                            const PixelAngleGrid& angles) {
  // Angular extent of the view and the samples inside it.
  const StrideGrid& grid = angles.grid();
  const int rows = grid.rows(), cols = grid.cols();
  float az0 = INFINITY, az1 = -INFINITY, el0 = INFINITY, el1 = -INFINITY;
  for (int r = 0; r < rows; ++r) {
    az0 = std::min({az0, angles.azimuthRow(r)[0], angles.azimuthRow(r)[cols - 1]});
    az1 = std::max({az1, angles.azimuthRow(r)[0], angles.azimuthRow(r)[cols - 1]});
    el0 = std::min(el0, angles.minElevation(r));
    el1 = std::max(el1, angles.maxElevation(r));
  }
  std::size_t in_view = 0;
  for (const AngularSample& s : samples) {
    in_view += s.depth > 0.0f && s.azimuth_deg >= az0 && s.azimuth_deg <= az1 &&
               s.elevation_deg >= el0 && s.elevation_deg <= el1;
  }
  if (in_view == 0) return std::numeric_limits<double>::infinity();
  return std::sqrt(double(az1 - az0) * double(el1 - el0) / double(in_view));
}

double denseEdgeRatio(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                      const GroundPriorParams& ground) {
  if (!(ground.dense_edge_ratio_per_deg > 0.0)) return ground.dense_edge_ratio;
  const double spacing = meanSampleSpacingDeg(samples, angles);
  if (!std::isfinite(spacing)) return ground.dense_edge_ratio;
  return std::max(ground.dense_edge_ratio, ground.dense_edge_ratio_per_deg * spacing);
}

bool groundInputIsDense(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params) {
  using Input = GroundPriorParams::Input;
  if (params.ground.input != Input::kAuto) return params.ground.input == Input::kDense;
  // Dense when a neighbourhood of the reference radius holds on average more than ~4 pi samples:
  // the regime where the exact local GP solves hundreds of samples per set and where neighbour
  // sets stop repeating. Radar (VoD: ~3 deg apart) stays sparse, 1-in-4 LiDAR (~0.5 deg) is dense.
  return meanSampleSpacingDeg(samples, angles) <= 0.5 * params.radius_deg;
}

void predictGroundGpDense(const PixelAngleGrid& angles, const DepthCompletionParams& params,
                          const GroundPlane& plane, double median_depth, ThreadPool& pool,
                          PixelPredictions& out, ModelScratch& scratch,
                          BackgroundTriangulation& triangulation, const cv::Mat& image) {
  const GroundPriorParams& g = params.ground;
  const std::size_t n = static_cast<std::size_t>(angles.grid().size());
  // No fill: every pixel is written below, inside a triangle by the rasteriser, else by the gap
  // pass.
  out.mean.resize(n);
  out.variance.resize(n);
  // The triangulation (CGAL, serial: ~20 ms of a VoD HDL-64 frame) runs on its own thread, started
  // by the caller before the ground plane's fit, while the pool builds what does not depend on it:
  // the vote's bins, the gap fill's lattice and the column extension's top returns. Why: in order
  // it left the second core idle for a fifth of the frame. With a pool of one thread the caller
  // asked for one thread, and everything runs in order.
  const bool overlap = triangulation.started();
  // The samples the triangulation sees (those the camera can see, when hidden returns are dropped;
  // the filter runs first on the triangulation's thread), for every stage of this mode.
  const std::vector<AngularSample>& samples = triangulation.samples();
  // Occlusion edges are decided by the pixel's surface_k nearest samples (any triangle).
  const std::vector<AngularSample> usable = usableSamples(samples);
  const AngularBins bins(usable, kVoteBinDeg);
  // Tells the rasterising threads' vote memories and colour caches of this call from those of
  // earlier calls.
  static std::atomic<unsigned long long> calls{0};
  const unsigned long long frame = ++calls;
  const std::optional<VoteColours> vote_colours =
      g.dense_vote_colour_sigma > 0.0 && !image.empty()
          ? std::optional<VoteColours>(std::in_place, frame, image, angles, usable, g)
          : std::nullopt;
  // The nearest return's lattice for the gaps (outside the samples' hull): computed here while the
  // triangulation runs, else below only when there are gaps. A LiDAR image nearly always has them
  // (more than half of it lies above the highest ring).
  const int step = std::max(1, kFallbackStepPx / angles.grid().stride);
  std::optional<NearestSurfaceRows> gap_lattice;
  // So is what the column extension extends (the returns projected to the columns).
  std::optional<ColumnExtension> extension;
  if (overlap) {
    gap_lattice.emplace(nearestSurfaceRows(samples, angles, 1, 1, step, pool));
    extension.emplace(columnExtension(usable, angles, plane, pool));
  }
  std::vector<AngularTriangle> triangles = triangulation.get();
  const std::vector<TriangleMirrors>& mirrors = triangulation.mirrors();
  std::vector<DenseVertexInfo> info(triangles.size());
  const double ratio = 1.0 + g.dense_edge_ratio;
  const double rel2 = g.dense_relative_sigma * g.dense_relative_sigma;
  PerWorker<PlaneDepthCache> plane_depths(pool.size());
  pool.parallelFor(
      static_cast<long long>(triangles.size()),
      [&](long long i, int worker) {
        const AngularTriangle& t = triangles[i];
        DenseVertexInfo& v = info[i];
        for (int j = 0; j < 3; ++j) {
          const double plane_depth = plane_depths[worker](plane, t.az[j], t.el[j]);
          v.ground[j] = t.z[j] >= (1.0 - kGroundMargin) * plane_depth;
          v.plane_ratio[j] = v.ground[j] ? static_cast<float>(t.z[j] / plane_depth) : 0.0f;
          v.longest_edge_deg =
              std::max(j == 0 ? 0.0f : v.longest_edge_deg,
                       static_cast<float>(
                           std::hypot(t.az[j] - t.az[(j + 1) % 3], t.el[j] - t.el[(j + 1) % 3])));
        }
        v.edge = false;
        for (int a = 0; a < 3; ++a) {
          for (int b = 0; b < 3; ++b) {
            v.same[a][b] = (v.ground[a] && v.ground[b]) || depthsWithinRatio(t.z[a], t.z[b], ratio);
            v.edge |= !v.same[a][b];
          }
        }
        if (v.edge && i < static_cast<long long>(mirrors.size()) && onOnePlane(t, mirrors[i])) {
          v.edge = false;
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
              v.same[a][b] = true;
        }
      },
      1024);
  std::vector<std::uint8_t>& filled = scratch.filled;
  // Written wherever the rasteriser fills and meaningful only there (the column extension reads
  // every pixel's, branch-free, and ignores it where not filled): no fill per frame; resize()
  // value-initialises only new elements, so no read is of uninitialised memory.
  std::vector<float>& longest = scratch.longest_edge;
  longest.resize(n);
  const int cols = angles.grid().cols();
  // A pixel of an edge triangle (the vote decides its surface).
  const auto edge_pixel = [&](const AngularTriangle& t, double l0, double l1, double l2,
                              std::size_t pixel, float az, float el) {
    const double l[3] = {std::max(0.0, l0), std::max(0.0, l1), std::max(0.0, l2)};
    const DenseVertexInfo& v = info[&t - triangles.data()];
    longest[pixel] = v.longest_edge_deg;
    // The surface the pixel lies on: the vertex depth with the most support among the pixel's
    // nearest samples, each weighted by its inverse squared angular distance: a vote of
    // several returns, so that one stray return (a background return seen past the edge from
    // the LiDAR's viewpoint, a return through foliage) does not decide alone as it does for
    // the nearest-sample baseline. No support at all: the nearest vertex. (Triangles without an
    // edge, one surface, go through rasterizeSurfaceRow.)
    int j = 0;
    // A decisive vote (the winning surface has kVoteDecisiveRatio times the support of any
    // other) stands for the next kVoteReusePixels pixels of the same triangle row: the k
    // nearest returns of neighbouring pixels are nearly the same, and the queries were the
    // largest cost of the dense mode. Near a close vote every pixel queries.
    thread_local VoteMemory memory;
    if (memory.frame == frame && memory.triangle == &t && pixel == memory.pixel + 1 &&
        pixel % static_cast<std::size_t>(cols) != 0 && memory.reuses_left > 0) {
      j = memory.winner;
      --memory.reuses_left;
      memory.pixel = pixel;
    } else {
      j = nearestVertex(t, az, el);
      thread_local std::vector<std::pair<double, int>> nearest;
      voteNeighbours(frame, pixel, az, el, g.surface_k, bins, angles, nearest);
      // Each neighbour's weight and depth once (not once per vertex); each support still
      // sums its neighbours nearest first.
      double support[3] = {0.0, 0.0, 0.0};
      for (const auto& nn : nearest) {
        const double weight = 1.0 / (nn.first + kVoteDistanceFloorDeg2);
        const double depth = usable[nn.second].depth;
        for (int i = 0; i < 3; ++i) {
          if (depthsWithinRatio(depth, t.z[i], ratio)) support[i] += weight;
        }
      }
      if (vote_colours && !nearest.empty()) {
        const double say = vote_colours->say(nearest.front().first);
        if (say > 0.0)
          colourVote(*vote_colours, say, pixel, cols, nearest, usable, t, ratio, support);
      }
      double best = 0.0;
      for (int i = 0; i < 3; ++i) {
        if (support[i] > best) {
          best = support[i];
          j = i;
        }
      }
      double rival = 0.0;
      for (int i = 0; i < 3; ++i) {
        if (!v.same[i][j]) rival = std::max(rival, support[i]);
      }
      const bool decisive = best > 0.0 && best >= kVoteDecisiveRatio * rival;
      memory = {frame, &t, pixel, j, decisive ? kVoteReusePixels : 0};
    }
    double weight = 0.0, inverse = 0.0;
    for (int i = 0; i < 3; ++i) {
      if (i != j && !v.same[i][j]) continue;
      weight += l[i];
      inverse += l[i] / t.z[i];
    }
    if (!(weight > 0.0)) {  // the nearest vertex sits on the far edge (l[j] = 0)
      weight = 1.0;
      inverse = 1.0 / t.z[j];
    }
    double mean = weight / inverse;
    if (v.ground[j]) mean = groundAcrossEdge(t, v, l, pixel, cols, angles, plane, mean);
    // The surface's own uncertainty, plus the spread of all three depths: ~0 inside a surface,
    // the step height across an occlusion edge, where the pixel may belong to the other side.
    double spread = 0.0;
    for (int i = 0; i < 3; ++i)
      spread += l[i] * (t.z[i] - mean) * (t.z[i] - mean);
    out.mean[pixel] = static_cast<float>(mean);
    out.variance[pixel] = static_cast<float>(rel2 * mean * mean + spread);
    return true;
  };
  rasterizeTriangleRows(
      triangles, angles, pool, filled,
      [&](const AngularTriangle& t, const TriangleBoxRow& box, std::uint8_t* filled_row) {
        const DenseVertexInfo& v = info[&t - triangles.data()];
        if (v.edge) {
          rasterizeBoxRow(t, box, filled_row, edge_pixel);
          return;
        }
        thread_local SurfaceRowScratch scratch;
        rasterizeSurfaceRow(t, v.longest_edge_deg, rel2, box, filled_row,
                            out.mean.data() + box.row_offset, out.variance.data() + box.row_offset,
                            longest.data() + box.row_offset, scratch);
      });

  // Gaps (outside the samples' hull): the sparse mode's prior, and above the highest ring the
  // extension of each column's topmost return.
  bool gaps = false;
  for (std::uint8_t f : filled)
    gaps |= f == 0;
  if (!gaps) return;
  const double far = g.far_depth > 0.0 ? g.far_depth : std::max(median_depth, 1.0);
  // The nearest return's lattice, interpolated and combined with the ground at the gap pixels
  // only: more than half of a LiDAR image lies above the highest ring, but the rest is filled.
  if (!gap_lattice) gap_lattice.emplace(nearestSurfaceRows(samples, angles, 1, 1, step, pool));
  const NearestSurfaceRows& nearest = *gap_lattice;
  const PinholeIntrinsics& k = angles.intrinsics();
  const int stride = angles.grid().stride;
  // groundPriorDepthAt()'s normalised x of each column, for the pinhole pass.
  const std::vector<double> column_x = pinholeColumnX(angles);
  const GapRowConstants gap{plane.up.x(),
                            plane.up.y(),
                            plane.up.z(),
                            plane.height,
                            static_cast<float>(far),
                            g.relative_sigma,
                            g.relative_sigma_per_deg};
  pool.parallelFor(
      angles.grid().rows(),
      [&](long long r, int) {
        const NearestSurfaceRows::RowWeights w = nearest.row(static_cast<int>(r));
        const std::size_t row = std::size_t(r) * cols;
        if (!angles.distorted()) {
          fillGapRow(gap, column_x.data(), (r * stride - k.cy) / k.fy, w, nearest.has_depth, cols,
                     filled.data() + row, out.mean.data() + row, out.variance.data() + row);
          return;
        }
        for (int c = 0; c < cols; ++c) {
          const std::size_t p = row + c;
          if (filled[p]) continue;
          const float nearest_depth =
              nearest.has_depth ? NearestSurfaceRows::lerp(w.depth_lo[c], w.depth_hi[c], w.t)
                                : INFINITY;
          const float distance_deg =
              NearestSurfaceRows::lerp(w.distance_lo[c], w.distance_hi[c], w.t);
          float mean =
              std::min(groundPriorDepthAt(angles, plane, int(r), c, INFINITY), nearest_depth);
          if (!std::isfinite(mean)) mean = static_cast<float>(far);
          mean = std::max(mean, 0.1f);
          const float sigma =
              mean * static_cast<float>(g.relative_sigma + g.relative_sigma_per_deg * distance_deg);
          out.mean[p] = mean;
          out.variance[p] = sigma * sigma;
        }
      },
      16);
  if (!extension) extension.emplace(columnExtension(usable, angles, plane, pool));
  extendColumnsUpward(*extension, angles, filled, longest, g, pool, out);
}

}  // namespace multimodal_nvs
