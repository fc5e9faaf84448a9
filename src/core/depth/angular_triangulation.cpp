// Delaunay triangulation (cv::Subdiv2D) of samples in (azimuth, elevation). Each triangle gets a
// conservative pixel box derived from the inverse pixel-angle mapping; the inside test of the
// rasteriser uses the pixel's own float32 angles, so interpolation is exact in the angular domain.
#include "multimodal_nvs/core/depth/angular_triangulation.hpp"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {
namespace {

/// Pixel box (grid indices, inclusive, one pixel of margin) that contains the triangle's angular
/// bounding box. Returns false when it misses the grid.
bool pixelBox(const PinholeIntrinsics& k, const StrideGrid& grid, double az0, double az1,
              double el0, double el1, AngularTriangle& t) {
  constexpr double kLimit = 89.9;
  az0 = std::max(az0, -kLimit);
  az1 = std::min(az1, kLimit);
  el0 = std::max(el0, -kLimit);
  el1 = std::min(el1, kLimit);
  if (az0 > az1 || el0 > el1) return false;
  double u0 = 0, u1 = 0, v = 0, v0 = std::numeric_limits<double>::infinity(), v1 = -v0, u = 0;
  angularToPixel(k, az0, 0.0, &u0, &v);
  angularToPixel(k, az1, 0.0, &u1, &v);
  // v = cy - fy tan(el) / cos(az) is monotone in el and, for fixed el, extremal at the az ends
  // or at az = 0.
  const double az_candidates[3] = {az0, az1, std::min(std::max(0.0, az0), az1)};
  for (double a : az_candidates) {
    for (double e : {el0, el1}) {
      angularToPixel(k, a, e, &u, &v);
      v0 = std::min(v0, v);
      v1 = std::max(v1, v);
    }
  }
  if (k.distortion.any()) {
    // Through a lens the box's edges bend: take the extremes over a 5x5 lattice of the angular
    // box (ends, quarters, the axis crossing) and widen by a pixel a side below.
    u0 = v0 = std::numeric_limits<double>::infinity();
    u1 = v1 = -u0;
    const auto lattice = [](double lo, double hi, int i) {
      return i < 4 ? lo + (hi - lo) * i / 3.0 : std::min(std::max(0.0, lo), hi);
    };
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j < 5; ++j) {
        if (!angularToPixel(k, lattice(az0, az1, i), lattice(el0, el1, j), &u, &v)) continue;
        u0 = std::min(u0, u);
        u1 = std::max(u1, u);
        v0 = std::min(v0, v);
        v1 = std::max(v1, v);
      }
    }
    if (!(u0 <= u1 && v0 <= v1)) return false;
    u0 -= grid.stride;
    u1 += grid.stride;
    v0 -= grid.stride;
    v1 += grid.stride;
  }
  const double s = grid.stride;
  t.col0 = static_cast<int>(std::max(-1.0, std::floor(u0 / s) - 1));
  t.col1 = static_cast<int>(std::min<double>(grid.cols(), std::ceil(u1 / s) + 1));
  t.row0 = static_cast<int>(std::max(-1.0, std::floor(v0 / s) - 1));
  t.row1 = static_cast<int>(std::min<double>(grid.rows(), std::ceil(v1 / s) + 1));
  t.col0 = std::max(0, t.col0);
  t.row0 = std::max(0, t.row0);
  t.col1 = std::min(grid.cols() - 1, t.col1);
  t.row1 = std::min(grid.rows() - 1, t.row1);
  return t.col0 <= t.col1 && t.row0 <= t.row1;
}

}  // namespace

std::vector<AngularTriangle> triangulateSamples(const std::vector<AngularSample>& all_samples,
                                                const PixelAngleGrid& angles) {
  const StrideGrid& grid = angles.grid();
  // The image's angular extent, and the samples near it.
  const AngularBox image = angles.extent();
  const float paz0 = image.az_min, paz1 = image.az_max, pel0 = image.el_min, pel1 = image.el_max;
  const float margin_az = std::max(2.0f, 0.1f * (paz1 - paz0));
  const float margin_el = std::max(2.0f, 0.1f * (pel1 - pel0));
  std::vector<AngularSample> samples;
  for (const AngularSample& s : usableSamples(all_samples)) {
    if (s.azimuth_deg >= paz0 - margin_az && s.azimuth_deg <= paz1 + margin_az &&
        s.elevation_deg >= pel0 - margin_el && s.elevation_deg <= pel1 + margin_el) {
      samples.push_back(s);
    }
  }
  if (samples.size() < 3) return {};

  // Insertion in elevation-then-azimuth order keeps Subdiv2D's point location walks short.
  std::vector<int> order(samples.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = int(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (samples[a].elevation_deg != samples[b].elevation_deg) {
      return samples[a].elevation_deg < samples[b].elevation_deg;
    }
    return samples[a].azimuth_deg < samples[b].azimuth_deg;
  });
  const AngularBox box = boundingBox(samples);
  const int x = static_cast<int>(std::floor(box.az_min)) - 2;
  const int y = static_cast<int>(std::floor(box.el_min)) - 2;
  cv::Subdiv2D subdiv(cv::Rect(x, y, static_cast<int>(std::ceil(box.az_max)) + 2 - x,
                               static_cast<int>(std::ceil(box.el_max)) + 2 - y));
  // Subdiv2D vertex id -> depth; a repeated direction returns the existing vertex: keep the
  // nearest return there.
  std::vector<double> vertex_depth;
  for (int i : order) {
    const int id = subdiv.insert(cv::Point2f(samples[i].azimuth_deg, samples[i].elevation_deg));
    if (id >= static_cast<int>(vertex_depth.size())) {
      vertex_depth.resize(id + 1, std::numeric_limits<double>::quiet_NaN());
    }
    const double z = samples[i].depth;
    if (!(vertex_depth[id] <= z)) vertex_depth[id] = z;
  }

  // Triangles whose three vertices are real samples (Subdiv2D's virtual outer vertices have ids < 4
  // and deleted edges report vertex 0; both have no depth).
  std::vector<int> leading;
  subdiv.getLeadingEdgeList(leading);
  std::vector<AngularTriangle> triangles;
  triangles.reserve(leading.size());
  const PinholeIntrinsics& k = angles.intrinsics();
  for (int edge : leading) {
    AngularTriangle t;
    bool ok = true;
    int e = edge;
    for (int j = 0; j < 3 && ok; ++j) {
      cv::Point2f p;
      const int id = subdiv.edgeOrg(e, &p);
      ok = id >= 4 && id < static_cast<int>(vertex_depth.size()) && std::isfinite(vertex_depth[id]);
      if (ok) {
        t.az[j] = p.x;
        t.el[j] = p.y;
        t.z[j] = vertex_depth[id];
      }
      e = subdiv.getEdge(e, cv::Subdiv2D::NEXT_AROUND_LEFT);
    }
    if (!ok || e != edge) continue;  // not a closed triangle
    t.det = (t.az[1] - t.az[0]) * (t.el[2] - t.el[0]) - (t.az[2] - t.az[0]) * (t.el[1] - t.el[0]);
    if (!(std::abs(t.det) > 1e-12)) continue;  // degenerate (collinear) triangle
    const double taz0 = std::min({t.az[0], t.az[1], t.az[2]});
    const double taz1 = std::max({t.az[0], t.az[1], t.az[2]});
    const double tel0 = std::min({t.el[0], t.el[1], t.el[2]});
    const double tel1 = std::max({t.el[0], t.el[1], t.el[2]});
    if (pixelBox(k, grid, taz0, taz1, tel0, tel1, t)) triangles.push_back(t);
  }

  return triangles;
}

}  // namespace multimodal_nvs
