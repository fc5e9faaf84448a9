#pragma once
// Delaunay triangulation of angular samples and rasterisation of its triangles onto the stride
// grid: shared by the `linear` baseline and the dense-input mode of `ground_gp`.
#include <algorithm>
#include <cstdint>
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

/// Delaunay triangles (CGAL, exact predicates) of the usable samples within 10 % of the image's
/// angular extent (at least 2 deg) around it, so 360-degree LiDAR does not pay for points far
/// outside the view. Samples with identical angles keep the nearest depth. Slivers along the convex
/// hull (those whose circumcircle reaches a far virtual vertex), degenerate triangles and those
/// missing the grid are dropped. Fewer than three samples: no triangle.
std::vector<AngularTriangle> triangulateSamples(const std::vector<AngularSample>& samples,
                                                const PixelAngleGrid& angles);

/// Calls `f(triangle, l0, l1, l2, pixel, az, el)` with the barycentric coordinates and the angles
/// of every grid pixel inside a triangle (angular domain, each pixel's own float32 angles). `f`
/// returns true when it wrote the pixel; the first triangle that writes a pixel wins (on a shared
/// edge both interpolate the same value). `filled` (grid size) marks written pixels. Row bands run
/// in parallel.
template <typename F>
void rasterizeTriangles(const std::vector<AngularTriangle>& triangles, const PixelAngleGrid& angles,
                        ThreadPool& pool, std::vector<std::uint8_t>& filled, F&& f) {
  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  filled.assign(static_cast<std::size_t>(rows) * cols, 0);
  const int band_rows = 16;
  const int bands = (rows + band_rows - 1) / band_rows;
  constexpr double kInsideTolerance = -1e-7;
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
    for (int k = band_start[b]; k < band_start[b + 1]; ++k) {
      const AngularTriangle& t = triangles[band_triangles[k]];
      const double inv_det = 1.0 / t.det;
      for (int r = std::max(r_begin, t.row0); r <= std::min(r_end - 1, t.row1); ++r) {
        const float* az = angles.azimuthRow(r);
        const float* el = angles.elevationRow(r);
        const std::size_t row = std::size_t(r) * cols;
        for (int c = t.col0; c <= t.col1; ++c) {
          if (filled[row + c]) continue;
          const double pa = double(az[c]) - t.az[0], pe = double(el[c]) - t.el[0];
          const double l1 = (pa * (t.el[2] - t.el[0]) - (t.az[2] - t.az[0]) * pe) * inv_det;
          const double l2 = ((t.az[1] - t.az[0]) * pe - pa * (t.el[1] - t.el[0])) * inv_det;
          const double l0 = 1.0 - l1 - l2;
          if (l0 < kInsideTolerance || l1 < kInsideTolerance || l2 < kInsideTolerance) continue;
          if (f(t, l0, l1, l2, row + c, az[c], el[c])) filled[row + c] = 1;
        }
      }
    }
  });
}

}  // namespace multimodal_nvs
