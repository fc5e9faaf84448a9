#include "multimodal_nvs/core/depth/ground_prior.hpp"

#include "multimodal_nvs/core/common/per_worker.hpp"
#include "multimodal_nvs/core/depth/angular_bins.hpp"
#include "multimodal_nvs/core/depth/look_alike_fill.hpp"

#include <Eigen/Geometry>  // cross
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace multimodal_nvs {

GroundPlane GroundPlane::fromCameraToWorld(const Eigen::Matrix4d& camera_to_world) {
  GroundPlane plane;
  // World up (0, 0, 1) in camera coordinates is the third row of the camera-to-world rotation.
  plane.up = camera_to_world.block<1, 3>(2, 0).transpose().normalized();
  plane.height = camera_to_world(2, 3);
  return plane;
}

GroundPlane GroundPlane::fromAngles(double height, double pitch_deg, double roll_deg) {
  const double pitch = pitch_deg * M_PI / 180.0, roll = roll_deg * M_PI / 180.0;
  GroundPlane plane;
  plane.up = {std::cos(pitch) * std::sin(roll), -std::cos(pitch) * std::cos(roll), std::sin(pitch)};
  plane.height = height;
  return plane;
}

std::array<Eigen::Vector3d, 4> GroundPlane::patchCorners(double near, double far,
                                                         double half_width) const {
  const Eigen::Vector3d optical_axis = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d forward = (optical_axis - optical_axis.dot(up) * up).normalized();
  const Eigen::Vector3d right = forward.cross(up);  // camera +x for a level camera
  const Eigen::Vector3d foot = -height * up;        // the road below the camera
  return {foot + near * forward - half_width * right, foot + near * forward + half_width * right,
          foot + far * forward + half_width * right, foot + far * forward - half_width * right};
}

Eigen::Vector2d normalisedFromAngles(double azimuth_deg, double elevation_deg) {
  // az = atan2(X, Z) and el = atan2(-Y, hypot(X, Z)) inverted for Z = 1.
  const double az = azimuth_deg * M_PI / 180.0, el = elevation_deg * M_PI / 180.0;
  return {std::tan(az), -std::tan(el) / std::cos(az)};
}

namespace {
/// One row of a pinhole camera's ground prior from its columns' x (a function of its own with
/// restrict pointers so that it vectorises).
void groundPriorRow(const double* __restrict xs, int cols, double up_x, double up_y, double up_z,
                    double height, double far_depth, float* __restrict row) {
  for (int c = 0; c < cols; ++c) {
    const double descent = up_x * xs[c] + up_y + up_z;
    const double depth = descent < 0.0 ? -height / descent : INFINITY;
    row[c] = static_cast<float>(std::min(depth, far_depth));
  }
}
}  // namespace

GroundPriorRows::GroundPriorRows(const PixelAngleGrid& angles, const GroundPlane& plane,
                                 double far_depth)
    : angles_(angles), plane_(plane), far_depth_(far_depth) {
  if (angles.distorted()) return;
  const PinholeIntrinsics& k = angles.intrinsics();
  const int cols = angles.grid().cols(), stride = angles.grid().stride;
  column_x_.resize(cols);
  for (int c = 0; c < cols; ++c)
    column_x_[c] = (c * stride - k.cx) / k.fx;
}

void GroundPriorRows::row(int r, float* out) const {
  const int cols = angles_.grid().cols();
  if (angles_.distorted()) {
    for (int c = 0; c < cols; ++c)
      out[c] = groundPriorDepthAt(angles_, plane_, r, c, far_depth_);
    return;
  }
  // A pinhole camera's rays are separable (a column's x, a row's y): groundPriorDepthAt's
  // arithmetic with the ray terms hoisted and the branch as a select, so that each row vectorises
  // (as a loop of calls this full-image pass took ~3 ms of VoD's 2.35 M pixels).
  const PinholeIntrinsics& k = angles_.intrinsics();
  const double up_y = plane_.up.y() * ((r * angles_.grid().stride - k.cy) / k.fy);
  groundPriorRow(column_x_.data(), cols, plane_.up.x(), up_y, plane_.up.z(), plane_.height,
                 far_depth_, out);
}

std::vector<float> groundPriorDepth(const PixelAngleGrid& angles, const GroundPlane& plane,
                                    double far_depth, ThreadPool* pool) {
  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  std::vector<float> prior(std::size_t(rows) * cols);
  const GroundPriorRows prior_rows(angles, plane, far_depth);
  parallelForOrInline(
      pool, rows, [&](long long r, int) { prior_rows.row(int(r), prior.data() + r * cols); }, 16);
  return prior;
}

namespace {

// Up to this many samples a vectorised distance pass over all of them beats the binned search
// (sparse radar: the k-th neighbour is degrees away and a binned query visits ~100 bins).
constexpr std::size_t kBruteForceMaxSamples = 4096;

// The samples in azimuth order: every sample within a radius of a query lies in the window of
// azimuths [query - radius, query + radius] (VoD radar, k = 8: about 60 of 225 object samples).
struct AzimuthOrder {
  std::vector<float> az, el;
  std::vector<int> index;  // the sample's position in the caller's order (breaks distance ties)
  bool windowed = true;    // false with non-finite angles: no order, every search is a full one
};

AzimuthOrder sortByAzimuth(const std::vector<AngularSample>& samples) {
  AzimuthOrder o;
  const std::size_t n = samples.size();
  o.index.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    o.index[i] = static_cast<int>(i);
    o.windowed &= std::isfinite(samples[i].azimuth_deg) && std::isfinite(samples[i].elevation_deg);
  }
  if (o.windowed) {
    std::sort(o.index.begin(), o.index.end(),
              [&](int a, int b) { return samples[a].azimuth_deg < samples[b].azimuth_deg; });
  }
  o.az.resize(n);
  o.el.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    o.az[i] = samples[o.index[i]].azimuth_deg;
    o.el[i] = samples[o.index[i]].elevation_deg;
  }
  return o;
}

// Positions [lo, hi) of an AzimuthOrder.
struct Window {
  std::size_t lo, hi;
};

// The window of every sample within `radius` of azimuth qaz, or all samples (no order, or a
// radius that is +inf, NaN or too large to matter). The reach exceeds the radius by a margin far
// above the float rounding of qaz +- reach and of the distance terms, so a sample outside has a
// squared distance above float(radius^2). Found by walking from the previous node's window:
// neighbouring nodes have nearby windows, so this beats two binary searches.
Window azimuthWindow(const AzimuthOrder& o, float qaz, double radius, Window previous) {
  const std::size_t n = o.az.size();
  if (!o.windowed || !(radius < 1e6)) return {0, n};
  const float reach = static_cast<float>(radius * 1.001 + 1e-3);
  const float low = qaz - reach, high = qaz + reach;
  const float* az = o.az.data();
  // lo: the first azimuth >= low; hi: the first one > high.
  std::size_t lo = previous.lo, hi = previous.hi;
  while (lo > 0 && az[lo - 1] >= low)
    --lo;
  while (lo < n && az[lo] < low)
    ++lo;
  hi = std::max(hi, lo);
  while (hi > lo && az[hi - 1] > high)
    --hi;
  while (hi < n && az[hi] <= high)
    ++hi;
  return {lo, hi};
}

// Up to this many values, a selection counts each one's rank: a few vectorised comparisons
// instead of sorting, whose unpredictable branches cost more at this size.
constexpr std::size_t kRankSelectMax = 32;

// Per-worker buffers of the brute-force searches, sized once and reused by every lattice node.
struct BruteForceScratch {
  std::vector<float> d2;
  std::vector<int> candidates;
  std::vector<std::uint64_t> keys;  // the candidates' distanceKey()
  std::vector<std::uint64_t> best;  // the kk nearest as distanceKey(), ascending (+1 spare slot)
  std::vector<float> depths;
  std::vector<int> nearest;    // the k nearest samples (indices into the front samples)
  std::vector<float> weights;  // their colour weights (nearestSurfaceRows with colours)
};

// (squared distance, index) as one integer that orders like the pair (non-negative floats order
// like their bit patterns): one comparison per step of a selection, ties to the lower index.
inline std::uint64_t distanceKey(float d2, int index) {
  std::uint32_t bits;
  std::memcpy(&bits, &d2, sizeof bits);
  return (std::uint64_t(bits) << 32) | static_cast<std::uint32_t>(index);
}
inline float keyDistance(std::uint64_t key) {
  const std::uint32_t bits = static_cast<std::uint32_t>(key >> 32);
  float d2;
  std::memcpy(&d2, &bits, sizeof d2);
  return d2;
}
inline int keyIndex(std::uint64_t key) {
  return static_cast<int>(key & 0xffffffffu);
}

// Squared distances from the query to the samples of a window, in one vectorised pass.
void squaredDistances(const AzimuthOrder& o, Window w, float qaz, float qel, float* __restrict d) {
  const float* __restrict a = o.az.data() + w.lo;
  const float* __restrict e = o.el.data() + w.lo;
  for (std::size_t i = 0, n = w.hi - w.lo; i < n; ++i) {
    const float da = a[i] - qaz, de = e[i] - qel;
    d[i] = da * da + de * de;
  }
}

// The smallest squared distance from the query to the samples of a non-empty window. A minimum
// of floats does not vectorise (the compiler keeps the NaN behaviour of each comparison), one of
// their bit patterns does: non-negative floats order like their bits, and NaN, above +inf, never
// wins, as with std::min_element. A NaN first distance, which min_element keeps, is kept too.
float nearestSquaredDistance(const AzimuthOrder& o, Window w, float qaz, float qel) {
  const float* __restrict a = o.az.data() + w.lo;
  const float* __restrict e = o.el.data() + w.lo;
  std::uint32_t best = 0xffffffffu;
  for (std::size_t i = 0, n = w.hi - w.lo; i < n; ++i) {
    const float da = a[i] - qaz, de = e[i] - qel;
    const float d = da * da + de * de;
    std::uint32_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    best = std::min(best, bits);
  }
  const float da = a[0] - qaz, de = e[0] - qel, first = da * da + de * de;
  if (std::isnan(first)) return first;
  float nearest;
  std::memcpy(&nearest, &best, sizeof nearest);
  return nearest;
}

// The kk nearest samples of a window within squared distance `limit` (+inf: all of them), into
// s.best ascending by (squared distance, index in the caller's order); false when fewer than kk
// are that near. A window covering every sample within the limit and holding kk of them gives
// the kk nearest of all samples, ties at the k-th distance going to the lower index (as
// nth_element on (distance, index) pairs did): every sample left out is farther than every
// candidate. The limit leaves few candidates (about 11 of a 60-sample window for radar, k = 8).
bool nearestInWindow(const AzimuthOrder& o, Window w, float qaz, float qel, std::size_t kk,
                     float limit, BruteForceScratch& s) {
  const std::size_t n = w.hi - w.lo;
  if (n < kk) return false;
  float* __restrict d = s.d2.data();
  squaredDistances(o, w, qaz, qel, d);
  const bool all = limit == INFINITY;
  std::size_t m = n;
  int* __restrict candidates = s.candidates.data();
  if (!all) {
    m = 0;
    for (std::size_t i = 0; i < n; ++i) {  // branch-free: the test is a coin flip near the edge
      candidates[m] = static_cast<int>(i);
      m += d[i] <= limit;
    }
    if (m < kk) return false;
  }
  const int* index = o.index.data() + w.lo;
  std::uint64_t* __restrict keys = s.keys.data();
  for (std::size_t t = 0; t < m; ++t) {
    const std::size_t i = all ? t : static_cast<std::size_t>(candidates[t]);
    keys[t] = distanceKey(d[i], index[i]);
  }
  std::uint64_t* __restrict best = s.best.data();
  if (m <= kRankSelectMax) {
    // Few candidates: each one's rank among them by counting (no branch to mispredict, and the
    // count vectorises). Keys are distinct, so the ranks below kk place the kk nearest in order;
    // the others land in the spare last slot.
    const std::size_t padded = (m + 7) / 8 * 8;
    std::fill(keys + m, keys + padded, ~std::uint64_t(0));
    for (std::size_t t = 0; t < m; ++t) {
      const std::uint64_t key = keys[t];
      std::size_t rank = 0;
      for (std::size_t u = 0; u < padded; ++u)
        rank += keys[u] < key;
      best[std::min(rank, kk)] = key;
    }
    return true;
  }
  // Many (a search of all samples, about once per lattice row): an insertion-sorted list of the
  // kk best, each insertion costing at most kk moves.
  std::size_t size = 0;
  for (std::size_t t = 0; t < m; ++t) {
    const std::uint64_t key = keys[t];
    if (size == kk) {
      if (key >= best[kk - 1]) continue;
      --size;
    }
    std::size_t p = size++;
    for (; p > 0 && best[p - 1] > key; --p)
      best[p] = best[p - 1];
    best[p] = key;
  }
  return true;
}

// The pick-th smallest value (0: the smallest) of d (no NaN), which may be reordered. A few
// values: the one with at most pick values below it and more than pick not above it, found by
// counting (vectorised, no branch to mispredict).
float orderStatistic(std::vector<float>& d, std::size_t pick) {
  const std::size_t n = d.size();
  if (n > kRankSelectMax) {
    std::nth_element(d.begin(), d.begin() + pick, d.end());
    return d[pick];
  }
  const float* __restrict v = d.data();
  float value = v[0];
  for (std::size_t t = 0; t < n; ++t) {
    const float x = v[t];
    std::uint32_t below = 0, not_above = 0;
    for (std::size_t u = 0; u < n; ++u) {
      below += v[u] < x;
      not_above += v[u] <= x;
    }
    value = below <= pick && pick < not_above ? x : value;
  }
  return value;
}

// The next node's search radius from the last one: moving the query by delta moves the k-th
// distance by at most |delta| (plus a little for float rounding), so one window is enough.
double nextRadius(double kth_distance, float qaz, float qel, float next_az, float next_el) {
  const double da = double(next_az) - qaz, de = double(next_el) - qel;
  return (kth_distance + std::sqrt(da * da + de * de)) * 1.01;
}

// A look-alike return's depth at a lattice node of azimuth `node_azimuth_deg`: with walls, the
// wall along the view through it (wallDepth), else its own depth. Normalised image x = X / Z =
// tan(azimuth) (the angular convention), lens or not.
double lookAlikeDepth(const AngularSample& look_alike, float node_azimuth_deg,
                      const SurfacePriorImage& image) {
  if (!image.walls) return look_alike.depth;
  constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
  return wallDepth(std::tan(double(look_alike.azimuth_deg) * kDegToRad), look_alike.depth,
                   std::tan(double(node_azimuth_deg) * kDegToRad), image.wall_cap_m);
}

}  // namespace

NearestSurfaceRows nearestSurfaceRows(const std::vector<AngularSample>& samples,
                                      const PixelAngleGrid& angles, int k, int rank, int step,
                                      ThreadPool& pool, const std::vector<AngularSample>* support,
                                      const SurfacePriorImage& image) {
  const SurfaceColours* const colours = image.colours;
  const StrideGrid& grid = angles.grid();
  const int rows = grid.rows(), cols = grid.cols();
  NearestSurfaceRows out;
  out.cols = cols;
  step = std::max(1, step);
  out.step = step;
  // Only samples in front of the camera can be a pixel's surface.
  std::vector<AngularSample> front;
  for (const auto& s : samples) {
    if (s.depth > 0.0f) front.push_back(s);
  }
  // The support set's own search structure (only its nearest member is needed).
  std::vector<AngularSample> support_front;
  if (support != nullptr) {
    for (const auto& s : *support) {
      if (s.depth > 0.0f) support_front.push_back(s);
    }
  }
  const bool separate_support = support != nullptr;
  // Each front sample's colour, when the image weighs the samples.
  const std::vector<CellColour> front_colours =
      colours != nullptr ? colours->atSamples(front, angles) : std::vector<CellColour>{};
  // Lattice nodes at every step-th row/column plus the last one, so interpolation covers the grid.
  auto nodes = [step](int size) {
    std::vector<int> n;
    for (int i = 0; i < size; i += step)
      n.push_back(i);
    if (n.back() != size - 1) n.push_back(size - 1);
    return n;
  };
  out.node_rows = nodes(rows);
  if (front.empty() && support_front.empty()) {
    out.depth_rows.assign(out.node_rows.size() * cols, INFINITY);
    out.distance_rows.assign(out.node_rows.size() * cols, INFINITY);
    return out;
  }
  out.has_depth = !front.empty();
  const AngularBins bins(front, 1.0);
  const AngularBins support_bins(support_front, 1.0);
  const bool support_brute_force = support_front.size() <= kBruteForceMaxSamples;
  const AzimuthOrder support_order =
      support_brute_force ? sortByAzimuth(support_front) : AzimuthOrder{};
  const bool brute_force = front.size() <= kBruteForceMaxSamples;
  const AzimuthOrder front_order = brute_force ? sortByAzimuth(front) : AzimuthOrder{};
  const std::vector<int>& node_rows = out.node_rows;
  const std::vector<int> node_cols = nodes(cols);
  const std::size_t lattice_cols = node_cols.size();
  std::vector<float> node_depth(node_rows.size() * lattice_cols);
  std::vector<float> node_distance(node_rows.size() * lattice_cols);
  // k as a count of samples (k < 0: all of them, through the size_t cast).
  const std::size_t kk =
      std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(k), front.size()));
  PerWorker<BruteForceScratch> scratch(pool.size());
  for (int worker = 0; worker < scratch.size(); ++worker) {
    BruteForceScratch& s = scratch[worker];
    if (brute_force) {
      s.d2.resize(front.size());
      s.candidates.resize(front.size());
      s.keys.resize(front.size() + 8);
      s.best.resize(kk + 1);
    }
    s.depths.reserve(kk);
    s.nearest.reserve(kk);
    s.weights.reserve(kk);
  }
  PerWorker<std::vector<std::pair<double, int>>> binned(pool.size());
  // With colours: each node's chosen return when it looks like the node (else -1), for the nodes
  // that look like none of theirs (below).
  const bool fill_look_alikes = colours != nullptr && image.fill_deg > 0.0;
  std::vector<int> node_look_alike(fill_look_alikes ? node_rows.size() * lattice_cols : 0, -1);
  pool.parallelFor(static_cast<long long>(node_rows.size()), [&](long long i, int worker) {
    BruteForceScratch& s = scratch[worker];
    std::vector<std::pair<double, int>>& found = binned[worker];
    double previous_kth = 0.0;  // binned search: neighbouring nodes have similar k-th distances
    // Search radii of the brute-force searches from the previous node (+inf: search all).
    double radius = INFINITY, support_radius = INFINITY;
    Window window{0, 0}, support_window{0, 0};
    for (std::size_t j = 0; j < lattice_cols; ++j) {
      const int r = node_rows[i], c = node_cols[j];
      const float qaz = angles.azimuthRow(r)[c], qel = angles.elevationRow(r)[c];
      const bool last = j + 1 == lattice_cols;
      const float next_az = last ? qaz : angles.azimuthRow(r)[node_cols[j + 1]];
      const float next_el = last ? qel : angles.elevationRow(r)[node_cols[j + 1]];
      float support_distance = INFINITY;
      if (separate_support && !support_front.empty()) {
        double nearest_d2;
        if (support_brute_force) {
          // Exact when the window's nearest is within the radius (everything outside is not).
          support_window = azimuthWindow(support_order, qaz, support_radius, support_window);
          const Window w = support_window;
          float d2 = w.hi > w.lo ? nearestSquaredDistance(support_order, w, qaz, qel) : INFINITY;
          if (!(d2 <= static_cast<float>(support_radius * support_radius))) {
            d2 = nearestSquaredDistance(support_order, {0, support_front.size()}, qaz, qel);
          }
          nearest_d2 = d2;
          support_radius = nextRadius(std::sqrt(nearest_d2), qaz, qel, next_az, next_el);
        } else {
          support_bins.nearest(qaz, qel, 1, found);
          nearest_d2 = found.front().first;
        }
        support_distance = static_cast<float>(std::sqrt(nearest_d2));
      }
      if (front.empty()) {
        node_depth[i * lattice_cols + j] = INFINITY;
        node_distance[i * lattice_cols + j] = support_distance;
        continue;
      }
      // The squared distances of the nearest and the k-th nearest, and the depths of the k.
      double nearest_d2 = 0.0, kth = 0.0;
      std::vector<float>& d = s.depths;
      d.clear();
      if (brute_force) {
        window = azimuthWindow(front_order, qaz, radius, window);
        if (!nearestInWindow(front_order, window, qaz, qel, kk, static_cast<float>(radius * radius),
                             s)) {
          nearestInWindow(front_order, {0, front.size()}, qaz, qel, kk, INFINITY, s);
        }
        nearest_d2 = keyDistance(s.best[0]);
        kth = keyDistance(s.best[kk - 1]);
        radius = nextRadius(std::sqrt(kth), qaz, qel, next_az, next_el);
        s.nearest.clear();
        for (std::size_t t = 0; t < kk; ++t)
          s.nearest.push_back(keyIndex(s.best[t]));
      } else {
        bins.nearest(qaz, qel, k, found, previous_kth);
        nearest_d2 = found.front().first;
        s.nearest.clear();
        for (const auto& nn : found) {
          kth = std::max(kth, nn.first);
          s.nearest.push_back(nn.second);
        }
        previous_kth = std::sqrt(kth) * 1.1;
      }
      for (const int index : s.nearest)
        d.push_back(front[index].depth);
      const std::size_t pick = std::min<std::size_t>(std::max(rank, 1) - 1, d.size() - 1);
      if (colours != nullptr) {
        const CellColour node = colours->at(double(c) * grid.stride, double(r) * grid.stride);
        s.weights.clear();
        for (const int index : s.nearest)
          s.weights.push_back(colours->weight(node, front_colours[index]));
        const std::size_t chosen =
            weightedOrderStatistic(d, s.weights, (double(pick) + 0.5) / double(d.size()));
        double depth = d[chosen];
        if (s.weights[chosen] > kWallMinColourWeight) {
          depth = lookAlikeDepth(front[s.nearest[chosen]], qaz, image);
          if (fill_look_alikes) node_look_alike[i * lattice_cols + j] = s.nearest[chosen];
        }
        node_depth[i * lattice_cols + j] = static_cast<float>(depth);
      } else {
        node_depth[i * lattice_cols + j] = orderStatistic(d, pick);
      }
      node_distance[i * lattice_cols + j] =
          separate_support ? support_distance : static_cast<float>(std::sqrt(nearest_d2));
    }
  });
  if (fill_look_alikes) {
    // A node that looks like none of its returns takes the look-alike return of the nearest node
    // along its row or column that found one (look_alike_fill.hpp): a window its facade's wall.
    const int radius =
        nodesWithin(image.fill_deg, double(step) * grid.stride, angles.intrinsics().fx);
    const std::vector<int> nearest_look_alike =
        nearestLookAlikes(node_look_alike, static_cast<int>(node_rows.size()),
                          static_cast<int>(lattice_cols), radius);
    for (std::size_t i = 0; i < node_rows.size(); ++i) {
      for (std::size_t j = 0; j < lattice_cols; ++j) {
        const int look_alike = nearest_look_alike[i * lattice_cols + j];
        if (look_alike < 0) continue;
        const float qaz = angles.azimuthRow(node_rows[i])[node_cols[j]];
        node_depth[i * lattice_cols + j] =
            static_cast<float>(lookAlikeDepth(front[look_alike], qaz, image));
      }
    }
  }
  // Interpolation along each lattice row (the first half of the bilinear interpolation).
  out.depth_rows.assign(node_rows.size() * cols, INFINITY);
  out.distance_rows.resize(node_rows.size() * cols);
  pool.parallelFor(static_cast<long long>(node_rows.size()), [&](long long i, int) {
    const float* depth = node_depth.data() + i * lattice_cols;
    const float* distance = node_distance.data() + i * lattice_cols;
    float* depth_out = out.depth_rows.data() + i * cols;
    float* distance_out = out.distance_rows.data() + i * cols;
    // Span by span, so that the loop over a span's columns vectorises: columns [node j, node j + 1)
    // lie between nodes j and j + 1, those from the second-last node on (the last node's too)
    // between the last two nodes.
    for (std::size_t j = 0; j == 0 || j + 1 < lattice_cols; ++j) {
      const std::size_t j1 = std::min(j + 1, lattice_cols - 1);
      const int c0 = node_cols[j], c1 = node_cols[j1];
      const int end = j + 2 < lattice_cols ? c1 : cols;
      const float d0 = depth[j], d1 = depth[j1], s0 = distance[j], s1 = distance[j1];
      for (int c = c0; c < end; ++c) {
        const float tx = c1 > c0 ? float(c - c0) / float(c1 - c0) : 0.0f;
        if (!front.empty()) depth_out[c] = NearestSurfaceRows::lerp(d0, d1, tx);
        distance_out[c] = NearestSurfaceRows::lerp(s0, s1, tx);
      }
    }
  });
  return out;
}

NearestSurfaceRows::RowWeights NearestSurfaceRows::row(int r) const {
  const std::size_t n = node_rows.size();
  const std::size_t i = n == 1 ? 0 : std::min<std::size_t>(r / step, n - 2);
  const std::size_t i1 = std::min(i + 1, n - 1);
  const int r0 = node_rows[i], r1 = node_rows[i1];
  return {depth_rows.data() + i * cols, depth_rows.data() + i1 * cols,
          distance_rows.data() + i * cols, distance_rows.data() + i1 * cols,
          r1 > r0 ? float(r - r0) / float(r1 - r0) : 0.0f};
}

NearestSurface nearestSurfaceDepth(const std::vector<AngularSample>& samples,
                                   const PixelAngleGrid& angles, int k, int rank, int step,
                                   ThreadPool& pool, const std::vector<AngularSample>* support) {
  const NearestSurfaceRows lattice =
      nearestSurfaceRows(samples, angles, k, rank, step, pool, support);
  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  NearestSurface out;
  out.depth.assign(std::size_t(rows) * cols, INFINITY);
  out.distance_deg.resize(std::size_t(rows) * cols);
  pool.parallelFor(
      rows,
      [&](long long r, int) {
        const NearestSurfaceRows::RowWeights w = lattice.row(static_cast<int>(r));
        for (int c = 0; c < cols; ++c) {
          if (lattice.has_depth) {
            out.depth[r * cols + c] = NearestSurfaceRows::lerp(w.depth_lo[c], w.depth_hi[c], w.t);
          }
          out.distance_deg[r * cols + c] =
              NearestSurfaceRows::lerp(w.distance_lo[c], w.distance_hi[c], w.t);
        }
      },
      16);
  return out;
}

}  // namespace multimodal_nvs
