#include "multimodal_nvs/core/ground_prior.hpp"

#include "multimodal_nvs/core/angular_bins.hpp"

#include <algorithm>
#include <cmath>

namespace multimodal_nvs {

GroundPlane GroundPlane::fromCameraToWorld(const Eigen::Matrix4d& camera_to_world) {
  GroundPlane plane;
  // World up (0, 0, 1) in camera coordinates is the third row of the camera-to-world rotation.
  plane.up = camera_to_world.block<1, 3>(2, 0).transpose().normalized();
  plane.height = camera_to_world(2, 3);
  return plane;
}

Eigen::Vector2d normalisedFromAngles(double azimuth_deg, double elevation_deg) {
  // az = atan2(X, Z) and el = atan2(-Y, hypot(X, Z)) inverted for Z = 1.
  const double az = azimuth_deg * M_PI / 180.0, el = elevation_deg * M_PI / 180.0;
  return {std::tan(az), -std::tan(el) / std::cos(az)};
}

std::vector<float> groundPriorDepth(const PixelAngleGrid& angles, const GroundPlane& plane,
                                    double far_depth) {
  // Pixel rays straight from the intrinsics: the descent up . d is affine in (u, v).
  const PinholeIntrinsics& k = angles.intrinsics();
  const StrideGrid& grid = angles.grid();
  std::vector<float> prior(static_cast<std::size_t>(grid.size()));
  for (int r = 0; r < grid.rows(); ++r) {
    const double y = (r * grid.stride - k.cy) / k.fy;
    for (int c = 0; c < grid.cols(); ++c) {
      const double x = (c * grid.stride - k.cx) / k.fx;
      prior[std::size_t(r) * grid.cols() + c] =
          static_cast<float>(std::min(plane.depthAlong(x, y), far_depth));
    }
  }
  return prior;
}

namespace {

// Up to this many samples a vectorised distance pass over all of them beats the binned search
// (sparse radar: the k-th neighbour is degrees away and a binned query visits ~100 bins).
constexpr std::size_t kBruteForceMaxSamples = 4096;

// The k nearest of all samples by brute force: squared distances in one vectorised pass, then a
// selection among those within `hint` (a neighbouring query's k-th distance, degrees), or among
// all of them when fewer than k are that near. The samples of a scan often come sorted by
// azimuth, which makes a running "replace the worst" selection quadratic; this is not.
void nearestBruteForce(const std::vector<float>& az, const std::vector<float>& el, float qaz,
                       float qel, int k, double hint, std::vector<float>& d2,
                       std::vector<std::pair<double, int>>& out) {
  const std::size_t n = az.size();
  d2.resize(n);
  const float* __restrict a = az.data();
  const float* __restrict e = el.data();
  float* __restrict d = d2.data();
  for (std::size_t i = 0; i < n; ++i) {
    const float da = a[i] - qaz, de = e[i] - qel;
    d[i] = da * da + de * de;
  }
  const std::size_t kk = std::min<std::size_t>(k, n);
  out.clear();
  if (kk == 1) {  // the nearest alone: one linear scan, no selection
    const std::size_t best = static_cast<std::size_t>(std::min_element(d, d + n) - d);
    out.emplace_back(d[best], int(best));
    return;
  }
  if (hint > 0.0) {
    const float limit = static_cast<float>(hint * hint);
    for (std::size_t i = 0; i < n; ++i) {
      if (d[i] <= limit) out.emplace_back(d[i], int(i));
    }
  }
  if (out.size() < kk) {
    out.clear();
    for (std::size_t i = 0; i < n; ++i)
      out.emplace_back(d[i], int(i));
  }
  std::nth_element(out.begin(), out.begin() + (kk - 1), out.end());
  out.resize(kk);
  std::iter_swap(out.begin(), std::min_element(out.begin(), out.end()));
}

}  // namespace

NearestSurfaceRows nearestSurfaceRows(const std::vector<AngularSample>& samples,
                                      const PixelAngleGrid& angles, int k, int rank, int step,
                                      ThreadPool& pool, const std::vector<AngularSample>* support) {
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
  std::vector<float> support_az(support_front.size()), support_el(support_front.size());
  for (std::size_t i = 0; i < support_front.size(); ++i) {
    support_az[i] = support_front[i].azimuth_deg;
    support_el[i] = support_front[i].elevation_deg;
  }
  const bool brute_force = front.size() <= kBruteForceMaxSamples;
  std::vector<float> front_az(front.size()), front_el(front.size());
  for (std::size_t i = 0; i < front.size(); ++i) {
    front_az[i] = front[i].azimuth_deg;
    front_el[i] = front[i].elevation_deg;
  }
  std::vector<std::vector<float>> distances(pool.size());
  const std::vector<int>& node_rows = out.node_rows;
  const std::vector<int> node_cols = nodes(cols);
  const std::size_t lattice_cols = node_cols.size();
  std::vector<float> node_depth(node_rows.size() * lattice_cols);
  std::vector<float> node_distance(node_rows.size() * lattice_cols);
  std::vector<std::vector<std::pair<double, int>>> scratch(pool.size());
  std::vector<std::vector<float>> depths(pool.size());
  pool.parallelFor(static_cast<long long>(node_rows.size()), [&](long long i, int worker) {
    double previous_kth = 0.0;  // neighbouring nodes have similar k-th distances
    for (std::size_t j = 0; j < lattice_cols; ++j) {
      const int r = node_rows[i], c = node_cols[j];
      const float qaz = angles.azimuthRow(r)[c], qel = angles.elevationRow(r)[c];
      float support_distance = INFINITY;
      if (separate_support && !support_front.empty()) {
        if (support_brute_force) {
          nearestBruteForce(support_az, support_el, qaz, qel, 1, 0.0, distances[worker],
                            scratch[worker]);
        } else {
          support_bins.nearest(qaz, qel, 1, scratch[worker]);
        }
        support_distance = static_cast<float>(std::sqrt(scratch[worker].front().first));
      }
      if (front.empty()) {
        node_depth[i * lattice_cols + j] = INFINITY;
        node_distance[i * lattice_cols + j] = support_distance;
        continue;
      }
      if (brute_force) {
        nearestBruteForce(front_az, front_el, angles.azimuthRow(r)[c], angles.elevationRow(r)[c], k,
                          previous_kth, distances[worker], scratch[worker]);
      } else {
        bins.nearest(angles.azimuthRow(r)[c], angles.elevationRow(r)[c], k, scratch[worker],
                     previous_kth);
      }
      double kth = 0.0;
      for (const auto& nn : scratch[worker])
        kth = std::max(kth, nn.first);
      previous_kth = std::sqrt(kth) * 1.1;
      std::vector<float>& d = depths[worker];
      d.clear();
      for (const auto& nn : scratch[worker])
        d.push_back(front[nn.second].depth);
      const std::size_t pick = std::min<std::size_t>(std::max(rank, 1) - 1, d.size() - 1);
      std::nth_element(d.begin(), d.begin() + pick, d.end());
      node_depth[i * lattice_cols + j] = d[pick];
      node_distance[i * lattice_cols + j] =
          separate_support ? support_distance
                           : static_cast<float>(std::sqrt(scratch[worker].front().first));
    }
  });
  // Interpolation along each lattice row (the first half of the bilinear interpolation).
  out.depth_rows.assign(node_rows.size() * cols, INFINITY);
  out.distance_rows.resize(node_rows.size() * cols);
  pool.parallelFor(static_cast<long long>(node_rows.size()), [&](long long i, int) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t j =
          lattice_cols == 1 ? 0 : std::min<std::size_t>(c / step, lattice_cols - 2);
      const std::size_t j1 = std::min(j + 1, lattice_cols - 1);
      const int c0 = node_cols[j], c1 = node_cols[j1];
      const float tx = c1 > c0 ? float(c - c0) / float(c1 - c0) : 0.0f;
      auto lerp = [&](const std::vector<float>& v) {
        return (1 - tx) * v[i * lattice_cols + j] + tx * v[i * lattice_cols + j1];
      };
      if (!front.empty()) out.depth_rows[i * cols + c] = lerp(node_depth);
      out.distance_rows[i * cols + c] = lerp(node_distance);
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
