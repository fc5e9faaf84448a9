// Delaunay triangulation (CGAL) of samples in (azimuth, elevation). Each triangle gets a
// conservative pixel box derived from the inverse pixel-angle mapping; the inside test of the
// rasteriser uses the pixel's own float32 angles, so interpolation is exact in the angular domain.
#include "multimodal_nvs/core/depth/angular_triangulation.hpp"

#include "multimodal_nvs/core/depth/hidden_returns.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <system_error>
#include <utility>

#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/direction_sort.hpp"
#include "multimodal_nvs/core/depth/hidden_returns.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {
namespace {

// Exact predicates: the orientation and in-circle tests stay right on the near-collinear points
// of a LiDAR ring, where float arithmetic makes incremental Delaunay codes loop or fold.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;  // the sample index
using Delaunay = CGAL::Delaunay_triangulation_2<
    Kernel,
    CGAL::Triangulation_data_structure_2<VertexBase, CGAL::Triangulation_face_base_2<Kernel>>>;
using DelaunayPoint = Kernel::Point_2;

// The margin (grid pixels) of a pinhole camera's triangle box around the exact projection of the
// triangle's angular box. A pixel whose float32 angles lie in the triangle projects within ~1e-3
// px of that box (float32 angle error ~1e-6 deg, at most ~30 px per degree even 80 deg off axis),
// so 0.05 px loses no pixel. It was a whole pixel a side: on VoD's LiDAR triangles (~5 x 13 px)
// that made the rasteriser test ~4 box pixels per pixel inside.
constexpr double kPinholeBoxMarginPx = 0.05;
// Through a lens the box comes from a lattice of projections (its edges bend): a pixel a side.
constexpr double kLensBoxMarginPx = 1.0;

/// The grid box (inclusive, `margin` grid pixels a side, clipped to the grid) of a pixel range.
/// Returns false when it misses the grid.
bool pixelRangeToBox(const StrideGrid& grid, double u0, double u1, double v0, double v1,
                     double margin, AngularTriangle& t) {
  const double s = grid.stride;
  t.col0 = static_cast<int>(std::max(-1.0, std::floor(u0 / s - margin)));
  t.col1 = static_cast<int>(std::min<double>(grid.cols(), std::ceil(u1 / s + margin)));
  t.row0 = static_cast<int>(std::max(-1.0, std::floor(v0 / s - margin)));
  t.row1 = static_cast<int>(std::min<double>(grid.rows(), std::ceil(v1 / s + margin)));
  t.col0 = std::max(0, t.col0);
  t.row0 = std::max(0, t.row0);
  t.col1 = std::min(grid.cols() - 1, t.col1);
  t.row1 = std::min(grid.rows() - 1, t.row1);
  return t.col0 <= t.col1 && t.row0 <= t.row1;
}

/// Pixel box (grid indices, inclusive, with a margin) that contains the triangle's angular
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
    return pixelRangeToBox(grid, u0, u1, v0, v1, kLensBoxMarginPx, t);
  }
  return pixelRangeToBox(grid, u0, u1, v0, v1, kPinholeBoxMarginPx, t);
}

/// The pinhole projection's terms of one sample (radians of its float32 angles), computed once per
/// sample instead of once per triangle corner: with several triangles per sample and eight
/// projections per box, tan and cos were a fifth of the serial triangulation stage.
struct PinholeTerms {
  double tan_az, cos_az, tan_el;
};

PinholeTerms pinholeTerms(const AngularSample& s) {
  constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
  const double az = double(s.azimuth_deg) * kDegToRad, el = double(s.elevation_deg) * kDegToRad;
  return {std::tan(az), std::cos(az), std::tan(el)};
}

/// pixelBox() for an undistorted camera from the vertices' precomputed terms: the same arithmetic
/// as angularToPixel at the same angles (the box's ends are vertex angles, and its axis crossing
/// has tan 0 and cos 1 exactly), so the same box.
bool pinholePixelBox(const PinholeIntrinsics& k, const StrideGrid& grid,
                     const PinholeTerms* const p[3], AngularTriangle& t) {
  int a0 = 0, a1 = 0, e0 = 0, e1 = 0;  // the vertices of the extreme angles
  for (int j = 1; j < 3; ++j) {
    if (t.az[j] < t.az[a0]) a0 = j;
    if (t.az[j] > t.az[a1]) a1 = j;
    if (t.el[j] < t.el[e0]) e0 = j;
    if (t.el[j] > t.el[e1]) e1 = j;
  }
  const double u0 = pinholeColumn(k, p[a0]->tan_az);
  const double u1 = pinholeColumn(k, p[a1]->tan_az);
  // The az candidates of pixelBox: both ends and min(max(0, az0), az1).
  const double crossing_cos = t.az[a0] >= 0.0   ? p[a0]->cos_az
                              : t.az[a1] <= 0.0 ? p[a1]->cos_az
                                                : 1.0;
  const double cosines[3] = {p[a0]->cos_az, p[a1]->cos_az, crossing_cos};
  double v0 = std::numeric_limits<double>::infinity(), v1 = -v0;
  for (double c : cosines) {
    for (double tan_el : {p[e0]->tan_el, p[e1]->tan_el}) {
      const double v = pinholeRow(k, tan_el, c);
      v0 = std::min(v0, v);
      v1 = std::max(v1, v);
    }
  }
  return pixelRangeToBox(grid, u0, u1, v0, v1, kPinholeBoxMarginPx, t);
}

}  // namespace

std::vector<AngularTriangle> triangulateSamples(const std::vector<AngularSample>& all_samples,
                                                const PixelAngleGrid& angles,
                                                std::vector<TriangleMirrors>* mirrors) {
  if (mirrors) mirrors->clear();
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

  // One vertex per direction: a repeated direction keeps its nearest return (sorted by direction,
  // then depth, the first of each run).
  sortByDirectionThenDepth(samples);
  std::vector<std::pair<DelaunayPoint, int>> vertices;
  vertices.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (i > 0 && samples[i].azimuth_deg == samples[i - 1].azimuth_deg &&
        samples[i].elevation_deg == samples[i - 1].elevation_deg) {
      continue;
    }
    vertices.emplace_back(DelaunayPoint(samples[i].azimuth_deg, samples[i].elevation_deg), int(i));
  }
  // Three far virtual vertices, placed as cv::Subdiv2D places its outer triangle around the
  // samples' box (2 deg margin): triangles that touch them are dropped, and with them the long
  // slivers along the convex hull whose circumcircle reaches them, which no surface spans (the
  // hull's upper edge is the LiDAR's top ring). The same triangulation as before the move to CGAL.
  const AngularBox box = boundingBox(samples);
  const float x = std::floor(box.az_min) - 2.0f, y = std::floor(box.el_min) - 2.0f;
  const float big =
      3.0f * std::max(std::ceil(box.az_max) + 2.0f - x, std::ceil(box.el_max) + 2.0f - y);
  constexpr int kVirtual = -1;
  vertices.emplace_back(DelaunayPoint(x + big, y), kVirtual);
  vertices.emplace_back(DelaunayPoint(x, y + big), kVirtual);
  vertices.emplace_back(DelaunayPoint(x - big, y - big), kVirtual);
  // CGAL's range insertion sorts the points along a Hilbert curve first (spatial_sort), so every
  // point location walk is short; cv::Subdiv2D, inserting one by one, was the stage's main cost.
  const Delaunay delaunay(vertices.begin(), vertices.end());

  std::vector<AngularTriangle> triangles;
  triangles.reserve(2 * vertices.size());
  if (mirrors) mirrors->reserve(triangles.capacity());
  const PinholeIntrinsics& k = angles.intrinsics();
  // pixelBox() clamps angles beyond 89.9 deg (and 89.9f rounds above that double); a sample
  // nearer than a degree to the clamp takes the general path.
  constexpr float kPinholeTermsLimitDeg = 89.0f;
  std::vector<PinholeTerms> terms;
  std::vector<std::uint8_t> has_terms;
  if (!k.distortion.any()) {
    terms.resize(samples.size());
    has_terms.resize(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
      has_terms[i] = std::abs(samples[i].azimuth_deg) < kPinholeTermsLimitDeg &&
                     std::abs(samples[i].elevation_deg) < kPinholeTermsLimitDeg;
      if (has_terms[i]) terms[i] = pinholeTerms(samples[i]);
    }
  }
  for (auto face = delaunay.finite_faces_begin(); face != delaunay.finite_faces_end(); ++face) {
    if (face->vertex(0)->info() == kVirtual || face->vertex(1)->info() == kVirtual ||
        face->vertex(2)->info() == kVirtual) {
      continue;
    }
    AngularTriangle t;
    const PinholeTerms* vertex_terms[3] = {nullptr, nullptr, nullptr};
    bool precomputed = !terms.empty();
    for (int j = 0; j < 3; ++j) {
      const int index = face->vertex(j)->info();
      const AngularSample& s = samples[index];
      t.az[j] = s.azimuth_deg;
      t.el[j] = s.elevation_deg;
      t.z[j] = s.depth;
      if (precomputed) {
        precomputed = has_terms[index] != 0;
        vertex_terms[j] = &terms[index];
      }
    }
    t.det = (t.az[1] - t.az[0]) * (t.el[2] - t.el[0]) - (t.az[2] - t.az[0]) * (t.el[1] - t.el[0]);
    if (!(std::abs(t.det) > 1e-12)) continue;  // degenerate (collinear) triangle
    bool kept = false;
    if (precomputed) {
      kept = pinholePixelBox(k, grid, vertex_terms, t);
    } else {
      const double taz0 = std::min({t.az[0], t.az[1], t.az[2]});
      const double taz1 = std::max({t.az[0], t.az[1], t.az[2]});
      const double tel0 = std::min({t.el[0], t.el[1], t.el[2]});
      const double tel1 = std::max({t.el[0], t.el[1], t.el[2]});
      kept = pixelBox(k, grid, taz0, taz1, tel0, tel1, t);
    }
    if (!kept) continue;
    triangles.push_back(t);
    if (!mirrors) continue;
    TriangleMirrors m;
    for (int j = 0; j < 3; ++j) {
      m.vertex[j] = AngularSample{NAN, NAN, NAN};
      const auto neighbour = face->neighbor(j);
      if (delaunay.is_infinite(neighbour)) continue;
      const int index = delaunay.mirror_vertex(face, j)->info();
      if (index != kVirtual) m.vertex[j] = samples[index];
    }
    mirrors->push_back(m);
  }

  return triangles;
}

BackgroundTriangulation::BackgroundTriangulation(const std::vector<AngularSample>& samples,
                                                 const PixelAngleGrid& angles, bool start,
                                                 bool visible_only, double depth_ratio,
                                                 const Eigen::Vector3d& scan_origin,
                                                 bool with_mirrors)
    : samples_(samples),
      angles_(angles),
      visible_only_(visible_only),
      depth_ratio_(depth_ratio),
      scan_origin_(scan_origin),
      with_mirrors_(with_mirrors),
      visible_future_(visible_ready_.get_future().share()) {
  if (!start) return;
  try {
    triangles_ = std::async(std::launch::async, [this] {
      if (visible_only_) {
        try {
          visible_ =
              dropReturnsHiddenFromCamera(samples_, angles_, depth_ratio_, scan_origin_, &hidden_);
        } catch (...) {
          visible_ready_.set_exception(std::current_exception());
          throw;
        }
      }
      visible_ready_.set_value();
      return triangulateSamples(visible_only_ ? visible_ : samples_, angles_,
                                with_mirrors_ ? &mirrors_ : nullptr);
    });
  } catch (const std::system_error&) {
    // No thread to be had: samples() and get() work in the caller's thread.
  }
}

const std::vector<AngularSample>& BackgroundTriangulation::samples() {
  if (!visible_only_) return samples_;
  if (started()) {
    visible_future_.get();  // rethrows the filter's exception
  } else if (!filtered_) {
    visible_ = dropReturnsHiddenFromCamera(samples_, angles_, depth_ratio_, scan_origin_, &hidden_);
    filtered_ = true;
  }
  return visible_;
}

std::vector<AngularTriangle> BackgroundTriangulation::get() {
  return started() ? triangles_.get()
                   : triangulateSamples(samples(), angles_, with_mirrors_ ? &mirrors_ : nullptr);
}

}  // namespace multimodal_nvs
