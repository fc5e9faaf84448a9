#pragma once
// Delaunay triangulation of angular samples and rasterisation of its triangles onto the stride
// grid: shared by the `linear` baseline and the dense-input mode of `ground_gp`.
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <future>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// A triangle of samples in (azimuth, elevation) degrees with its vertex depths and the grid-pixel
/// box (inclusive) that contains it.
struct AngularTriangle {
  double az[3], el[3], z[3];
  double det;  // (p1 - p0) x (p2 - p0)
  int row0, row1, col0, col1;
};

/// The vertex across each edge of a triangle: vertex[i] is the third vertex of the Delaunay
/// triangle on the other side of the edge opposite the triangle's vertex i, depth NaN where there
/// is none (the hull). What a triangle's own three vertices cannot tell, its neighbours can:
/// whether its depths follow one plane (the dense mode of `ground_gp`).
struct TriangleMirrors {
  AngularSample vertex[3];
};

/// Delaunay triangles (CGAL, exact predicates) of the usable samples within 10 % of the image's
/// angular extent (at least 2 deg) around it, so 360-degree LiDAR does not pay for points far
/// outside the view. Samples with identical angles keep the nearest depth. Slivers along the convex
/// hull (those whose circumcircle reaches a far virtual vertex), degenerate triangles and those
/// missing the grid are dropped. Fewer than three samples: no triangle.
/// With `mirrors`, also each returned triangle's vertices across its edges, in the triangles'
/// order.
std::vector<AngularTriangle> triangulateSamples(const std::vector<AngularSample>& samples,
                                                const PixelAngleGrid& angles,
                                                std::vector<TriangleMirrors>* mirrors = nullptr);

/// triangulateSamples() on a thread of its own, started as early as the samples exist, so that the
/// serial triangulation (CGAL) overlaps whatever the caller does before it needs the triangles.
/// Without a thread to be had (a process at its limit), or when not asked to start early, get()
/// triangulates in the calling thread: the same triangles either way. With `visible_only`, what is
/// triangulated are the samples the camera can see (dropReturnsHiddenFromCamera with `depth_ratio`
/// and the scan's origin in the camera frame), filtered on the same thread first. With
/// `with_mirrors`, mirrors() holds the triangles' vertices across their edges after get().
class BackgroundTriangulation {
 public:
  BackgroundTriangulation(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                          bool start, bool visible_only = false, double depth_ratio = 1.1,
                          const Eigen::Vector3d& scan_origin = Eigen::Vector3d::Zero(),
                          bool with_mirrors = false);
  /// Whether the triangulation runs on its own thread.
  bool started() const { return triangles_.valid(); }
  /// The samples triangulated: all, or the visible ones (waits for the filter, not for the
  /// triangles). Valid as long as this object.
  const std::vector<AngularSample>& samples();
  /// The triangles (waits for the thread). Call once.
  std::vector<AngularTriangle> get();
  /// With `with_mirrors`, each triangle's vertices across its edges (after get(); empty without).
  const std::vector<TriangleMirrors>& mirrors() const { return mirrors_; }
  /// How many samples the filter left out (after samples()); -1 without the filter.
  long long hiddenCount() const { return visible_only_ ? static_cast<long long>(hidden_) : -1; }

 private:
  const std::vector<AngularSample>& samples_;
  const PixelAngleGrid& angles_;
  const bool visible_only_;
  const double depth_ratio_;
  const Eigen::Vector3d scan_origin_;
  const bool with_mirrors_;
  std::vector<TriangleMirrors> mirrors_;
  std::vector<AngularSample> visible_;
  std::size_t hidden_ = 0;
  bool filtered_ = false;  // visible_ holds the filter's result (calling thread only)
  std::promise<void> visible_ready_;
  std::shared_future<void> visible_future_;
  std::future<std::vector<AngularTriangle>> triangles_;
};

/// barycentricRow() works in whole blocks of this many pixels.
constexpr int kBarycentricBlock = 8;

/// A block of pixels' values (GCC/Clang vector extension: element-wise IEEE arithmetic, so a lane
/// computes exactly what the same scalar expression computes; this package compiles without
/// floating-point contraction). Spelled out because the compiler's own vectorisation of these
/// loops picks 32 pixels a step (the byte-wide inside flags set the width) and leaves every
/// narrower box row, nearly all of them, to its scalar remainder.
typedef double BlockDoubles __attribute__((vector_size(kBarycentricBlock * sizeof(double))));
typedef float BlockFloats __attribute__((vector_size(kBarycentricBlock * sizeof(float))));
typedef long long BlockMask __attribute__((vector_size(kBarycentricBlock * sizeof(long long))));

// Loads through an output reference: a 64-byte vector returned by value has another calling
// convention with AVX-512 than without (GCC's -Wpsabi on builds for CPUs without it).
inline void loadBlock(const double* p, BlockDoubles& v) {
  std::memcpy(&v, p, sizeof v);
}
inline void loadBlockAsDoubles(const float* p, BlockDoubles& v) {
  BlockFloats f;
  std::memcpy(&f, p, sizeof f);
  v = __builtin_convertvector(f, BlockDoubles);
}
inline void storeBlock(const BlockDoubles& v, double* p) {
  std::memcpy(p, &v, sizeof v);
}

/// The barycentric coordinates l1, l2 (l0 = 1 - l1 - l2) of n pixels with angles (az, el) in
/// triangle t, and whether each is inside it: no coordinate below -1e-7 (a NaN coordinate counts
/// as inside, as the scalar test `l < tolerance` lets it through). The arithmetic is that of a
/// scalar pixel loop, bit for bit. Works on n rounded up to whole kBarycentricBlock blocks: the
/// angles must be readable and the outputs writable that far (PixelAngleGrid's rows are, see
/// kRowReadPadding); the pixels past n get values nobody should read.
inline void barycentricRow(const AngularTriangle& t, const float* __restrict az,
                           const float* __restrict el, int n, double* __restrict l1s,
                           double* __restrict l2s, std::uint8_t* __restrict inside) {
  constexpr double kInsideTolerance = -1e-7;
  const double inv_det = 1.0 / t.det;
  const double az0 = t.az[0], el0 = t.el[0];
  const double d_az1 = t.az[1] - t.az[0], d_el1 = t.el[1] - t.el[0];
  const double d_az2 = t.az[2] - t.az[0], d_el2 = t.el[2] - t.el[0];
  for (int b = 0; b < n; b += kBarycentricBlock) {
    BlockDoubles pa, pe;
    loadBlockAsDoubles(az + b, pa);
    loadBlockAsDoubles(el + b, pe);
    pa -= az0;
    pe -= el0;
    const BlockDoubles l1 = (pa * d_el2 - d_az2 * pe) * inv_det;
    const BlockDoubles l2 = (d_az1 * pe - pa * d_el1) * inv_det;
    const BlockDoubles l0 = 1.0 - l1 - l2;
    storeBlock(l1, l1s + b);
    storeBlock(l2, l2s + b);
    const BlockMask in =
        ~(l0 < kInsideTolerance) & ~(l1 < kInsideTolerance) & ~(l2 < kInsideTolerance);
    for (int i = 0; i < kBarycentricBlock; ++i)
      inside[b + i] = static_cast<std::uint8_t>(in[i] & 1);
  }
}

/// One row of one triangle's box for rasterizeTriangleRows()'s callback: pixels [col0, col0 +
/// width) of the grid row that starts at `row_offset` (row * cols) in grid vectors, their angles
/// (`az[c]`, `el[c]` for column c) and, per box pixel i (column col0 + i), the barycentric
/// coordinates l1s[i], l2s[i] and whether it lies inside the triangle.
struct TriangleBoxRow {
  int col0 = 0;
  int width = 0;
  std::size_t row_offset = 0;
  const float* az = nullptr;
  const float* el = nullptr;
  const double* l1s = nullptr;
  const double* l2s = nullptr;
  const std::uint8_t* inside = nullptr;
};

/// Calls `f(triangle, box_row, filled_row)` for every row of every triangle's box that meets the
/// grid; `filled_row` points at the grid row's marks (column c at filled_row[c]). The callback
/// writes the pixels inside the triangle that are not yet filled and marks them: the first
/// triangle to write a pixel wins (on a shared edge both interpolate the same value). `filled`
/// (grid size) marks written pixels. Row bands run in parallel; a callback writes only its row.
template <typename F>
void rasterizeTriangleRows(const std::vector<AngularTriangle>& triangles,
                           const PixelAngleGrid& angles, ThreadPool& pool,
                           std::vector<std::uint8_t>& filled, F&& f) {
  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  static_assert(PixelAngleGrid::kRowReadPadding >= kBarycentricBlock,
                "barycentricRow reads whole blocks of a grid row");
  filled.assign(static_cast<std::size_t>(rows) * cols, 0);
  const int band_rows = 16;
  const int bands = (rows + band_rows - 1) / band_rows;
  // Each band's triangles, in the triangles' order (the first to write a pixel wins): walking all
  // triangles in every band read the whole list (~100 bytes a triangle) 76 times per VoD frame.
  std::vector<int> band_start(std::size_t(bands) + 1, 0), band_triangles;
  // Calls visit(band) for every band a triangle's rows meet.
  const auto forEachBand = [&](const AngularTriangle& t, auto&& visit) {
    if (t.row0 > t.row1 || t.row1 < 0 || t.row0 >= rows) return;
    for (int b = std::max(0, t.row0) / band_rows; b <= std::min(rows - 1, t.row1) / band_rows; ++b)
      visit(b);
  };
  for (const AngularTriangle& t : triangles)
    forEachBand(t, [&](int b) { ++band_start[b + 1]; });
  for (int b = 0; b < bands; ++b)
    band_start[b + 1] += band_start[b];
  band_triangles.resize(band_start[bands]);
  std::vector<int> next(band_start.begin(), band_start.end() - 1);
  for (std::size_t i = 0; i < triangles.size(); ++i)
    forEachBand(triangles[i], [&](int b) { band_triangles[next[b]++] = static_cast<int>(i); });
  pool.parallelFor(bands, [&](long long b, int) {
    const int r_begin = static_cast<int>(b) * band_rows;
    const int r_end = std::min(rows, r_begin + band_rows);
    // A row of a triangle's box: its barycentric coordinates, and whether each pixel is inside
    // (whole blocks: see barycentricRow).
    std::vector<double> l1s(std::size_t(cols) + kBarycentricBlock),
        l2s(std::size_t(cols) + kBarycentricBlock);
    std::vector<std::uint8_t> inside(std::size_t(cols) + kBarycentricBlock);
    for (int k = band_start[b]; k < band_start[b + 1]; ++k) {
      const AngularTriangle& t = triangles[band_triangles[k]];
      for (int r = std::max(r_begin, t.row0); r <= std::min(r_end - 1, t.row1); ++r) {
        const int width = t.col1 - t.col0 + 1;
        if (width <= 0) continue;
        const float* az = angles.azimuthRow(r);
        const float* el = angles.elevationRow(r);
        const std::size_t row = std::size_t(r) * cols;
        // Most of a box lies outside its triangle (5 of 6 pixels on a VoD LiDAR frame), so the
        // test runs on the whole row of the box at once (it vectorises) before any pixel is
        // written.
        barycentricRow(t, az + t.col0, el + t.col0, width, l1s.data(), l2s.data(), inside.data());
        f(t, TriangleBoxRow{t.col0, width, row, az, el, l1s.data(), l2s.data(), inside.data()},
          filled.data() + row);
      }
    }
  });
}

/// The per-pixel loop of one box row (rasterizeTriangles' callback form).
template <typename F>
void rasterizeBoxRow(const AngularTriangle& t, const TriangleBoxRow& box, std::uint8_t* filled_row,
                     F&& f) {
  for (int i = 0; i < box.width; ++i) {
    const int c = box.col0 + i;
    if (!box.inside[i] || filled_row[c]) continue;
    const double l1 = box.l1s[i], l2 = box.l2s[i], l0 = 1.0 - l1 - l2;
    if (f(t, l0, l1, l2, box.row_offset + c, box.az[c], box.el[c])) filled_row[c] = 1;
  }
}

/// Calls `f(triangle, l0, l1, l2, pixel, az, el)` with the barycentric coordinates and the angles
/// of every grid pixel inside a triangle (angular domain, each pixel's own float32 angles). `f`
/// returns true when it wrote the pixel; the first triangle that writes a pixel wins (on a shared
/// edge both interpolate the same value). `filled` (grid size) marks written pixels. Row bands run
/// in parallel.
template <typename F>
void rasterizeTriangles(const std::vector<AngularTriangle>& triangles, const PixelAngleGrid& angles,
                        ThreadPool& pool, std::vector<std::uint8_t>& filled, F&& f) {
  rasterizeTriangleRows(triangles, angles, pool, filled,
                        [&](const AngularTriangle& t, const TriangleBoxRow& box,
                            std::uint8_t* filled_row) { rasterizeBoxRow(t, box, filled_row, f); });
}

}  // namespace multimodal_nvs
