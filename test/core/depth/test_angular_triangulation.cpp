// The Delaunay triangulation of angular samples, its rasterisation, and the k-nearest searches over
// angular bins and gathered regions: the geometric structures of ground_gp's dense mode and the
// linear baseline.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_bins.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/angular_triangulation.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/region_nearest.hpp"

namespace mm = multimodal_nvs;

namespace {

// A 64x48 camera with ~1 deg pixels, about +-30 x +-22 deg.
const mm::PinholeIntrinsics kCamera(55.0, 55.0, 31.5, 23.5);
const mm::StrideGrid kGrid{{48, 64}, 1};

std::vector<mm::AngularSample> latticeSamples(float spacing_deg, float depth) {
  std::vector<mm::AngularSample> samples;
  for (float el = -20.0f; el <= 20.0f; el += spacing_deg) {
    for (float az = -28.0f; az <= 28.0f; az += spacing_deg)
      samples.push_back({az, el, depth});
  }
  return samples;
}

TEST(AngularTriangulation, CoversTheLatticeWithItsOwnSamplesOnly) {
  const std::vector<mm::AngularSample> samples = latticeSamples(4.0f, 10.0f);
  const mm::PixelAngleGrid angles(kCamera, kGrid);
  const std::vector<mm::AngularTriangle> triangles = mm::triangulateSamples(samples, angles);
  std::set<std::pair<float, float>> directions;
  for (const auto& s : samples)
    directions.insert({s.azimuth_deg, s.elevation_deg});
  // 15 x 11 lattice nodes: 2 x 14 x 10 triangles, every vertex a sample (no virtual vertex).
  EXPECT_EQ(triangles.size(), 2u * 14u * 10u);
  for (const auto& t : triangles) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_TRUE(directions.count({float(t.az[j]), float(t.el[j])}));
      EXPECT_EQ(t.z[j], 10.0);
    }
  }
  // Rasterised, every pixel inside the lattice's box gets exactly the lattice's depth.
  mm::ThreadPool pool(2);
  std::vector<std::uint8_t> filled;
  std::vector<double> depth(kGrid.size(), 0.0);
  mm::rasterizeTriangles(triangles, angles, pool, filled,
                         [&](const mm::AngularTriangle& t, double l0, double l1, double l2,
                             std::size_t pixel, float, float) {
                           depth[pixel] = l0 * t.z[0] + l1 * t.z[1] + l2 * t.z[2];
                           return true;
                         });
  int inside = 0;
  for (int r = 0; r < kGrid.rows(); ++r) {
    for (int c = 0; c < kGrid.cols(); ++c) {
      const float az = angles.azimuthRow(r)[c], el = angles.elevationRow(r)[c];
      if (az < -27.9f || az > 27.9f || el < -19.9f || el > 19.9f) continue;
      ++inside;
      EXPECT_TRUE(filled[std::size_t(r) * kGrid.cols() + c]) << r << " " << c;
      EXPECT_NEAR(depth[std::size_t(r) * kGrid.cols() + c], 10.0, 1e-9);
    }
  }
  EXPECT_GT(inside, 1000);
}

TEST(AngularTriangulation, ARepeatedDirectionKeepsItsNearestReturn) {
  std::vector<mm::AngularSample> samples = latticeSamples(8.0f, 20.0f);
  samples.push_back({4.0f, 4.0f, 30.0f});
  samples.push_back({4.0f, 4.0f, 5.0f});
  samples.push_back({4.0f, 4.0f, 12.0f});
  const mm::PixelAngleGrid angles(kCamera, kGrid);
  int seen = 0;
  for (const auto& t : mm::triangulateSamples(samples, angles)) {
    for (int j = 0; j < 3; ++j) {
      if (t.az[j] == 4.0 && t.el[j] == 4.0) {
        EXPECT_EQ(t.z[j], 5.0);
        ++seen;
      }
    }
  }
  EXPECT_GE(seen, 3);  // an interior vertex belongs to several triangles
}

TEST(AngularTriangulation, InTheBackgroundOrInOrderTheSameTriangles) {
  std::vector<mm::AngularSample> samples = latticeSamples(3.0f, 10.0f);
  for (std::size_t i = 0; i < samples.size(); i += 3)
    samples[i].depth = 4.0f + 0.01f * float(i);
  const mm::PixelAngleGrid angles(kCamera, kGrid);
  const std::vector<mm::AngularTriangle> expected = mm::triangulateSamples(samples, angles);
  ASSERT_GT(expected.size(), 100u);
  for (bool start : {true, false}) {
    mm::BackgroundTriangulation triangulation(samples, angles, start);
    EXPECT_EQ(triangulation.started(), start);
    const std::vector<mm::AngularTriangle> triangles = triangulation.get();
    ASSERT_EQ(triangles.size(), expected.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      for (int j = 0; j < 3; ++j) {
        EXPECT_EQ(triangles[i].az[j], expected[i].az[j]);
        EXPECT_EQ(triangles[i].el[j], expected[i].el[j]);
        EXPECT_EQ(triangles[i].z[j], expected[i].z[j]);
      }
      EXPECT_EQ(triangles[i].row0, expected[i].row0);
      EXPECT_EQ(triangles[i].col1, expected[i].col1);
    }
  }
}

TEST(AngularTriangulation, MirrorsAreTheVerticesAcrossEachEdge) {
  std::vector<mm::AngularSample> samples = latticeSamples(3.0f, 10.0f);
  for (std::size_t i = 0; i < samples.size(); ++i)
    samples[i].depth = 4.0f + 0.01f * float(i);  // tells the samples apart
  const mm::PixelAngleGrid angles(kCamera, kGrid);
  std::vector<mm::TriangleMirrors> mirrors;
  const std::vector<mm::AngularTriangle> triangles =
      mm::triangulateSamples(samples, angles, &mirrors);
  ASSERT_EQ(mirrors.size(), triangles.size());
  // Which side of the line through a and b a point lies on.
  const auto side = [](double az_a, double el_a, double az_b, double el_b, double az, double el) {
    return (az_b - az_a) * (el - el_a) - (el_b - el_a) * (az - az_a);
  };
  int across = 0, at_hull = 0;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const mm::AngularTriangle& t = triangles[i];
    for (int j = 0; j < 3; ++j) {
      const mm::AngularSample& m = mirrors[i].vertex[j];
      if (std::isnan(m.depth)) {
        ++at_hull;
        continue;
      }
      const int a = (j + 1) % 3, b = (j + 2) % 3;
      // A lattice neighbour on the other side of the edge opposite vertex j, not a vertex of t.
      const double own = side(t.az[a], t.el[a], t.az[b], t.el[b], t.az[j], t.el[j]);
      const double other = side(t.az[a], t.el[a], t.az[b], t.el[b], m.azimuth_deg, m.elevation_deg);
      EXPECT_LT(own * other, 0.0) << i << " " << j;
      EXPECT_LE(std::hypot(m.azimuth_deg - t.az[a], m.elevation_deg - t.el[a]), 3.0 * 1.5);
      bool found = false;  // one of the samples, with its own depth
      for (const mm::AngularSample& s : samples)
        found |= s.azimuth_deg == m.azimuth_deg && s.elevation_deg == m.elevation_deg &&
                 s.depth == m.depth;
      EXPECT_TRUE(found);
      ++across;
    }
  }
  EXPECT_GT(across, 2 * static_cast<int>(triangles.size()));
  EXPECT_GT(at_hull, 0);
  // On the triangulation's thread the same; without asking, none.
  mm::BackgroundTriangulation background(samples, angles, true, false, 1.1, Eigen::Vector3d::Zero(),
                                         true);
  ASSERT_EQ(background.get().size(), triangles.size());
  ASSERT_EQ(background.mirrors().size(), mirrors.size());
  for (std::size_t i = 0; i < mirrors.size(); ++i) {
    for (int j = 0; j < 3; ++j) {
      const mm::AngularSample &a = background.mirrors()[i].vertex[j], &b = mirrors[i].vertex[j];
      EXPECT_TRUE((std::isnan(a.depth) && std::isnan(b.depth)) ||
                  (a.azimuth_deg == b.azimuth_deg && a.elevation_deg == b.elevation_deg &&
                   a.depth == b.depth));
    }
  }
  mm::BackgroundTriangulation plain(samples, angles, true);
  plain.get();
  EXPECT_TRUE(plain.mirrors().empty());
}

TEST(AngularTriangulation, FewerThanThreeSamplesGiveNoTriangle) {
  const mm::PixelAngleGrid angles(kCamera, kGrid);
  EXPECT_TRUE(mm::triangulateSamples({{0.0f, 0.0f, 5.0f}, {1.0f, 0.0f, 5.0f}}, angles).empty());
}

// 3,000 random directions over 80 x 20 deg, plus one repeated direction (ties broken by index).
const std::uniform_real_distribution<float> kRandomAzimuth(-40.0f, 40.0f);
const std::uniform_real_distribution<float> kRandomElevation(-15.0f, 5.0f);
std::vector<mm::AngularSample> randomSamples(std::mt19937& random) {
  auto az = kRandomAzimuth;
  auto el = kRandomElevation;
  std::vector<mm::AngularSample> samples(3000);
  for (auto& s : samples)
    s = {az(random), el(random), 10.0f};
  samples.push_back(samples[17]);
  return samples;
}

/// The k samples nearest to (az, el) as (squared distance, index), nearest first, ties by index.
std::vector<std::pair<double, int>> bruteForceNearest(const std::vector<mm::AngularSample>& samples,
                                                      double az, double el, int k) {
  std::vector<std::pair<double, int>> all;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double da = samples[i].azimuth_deg - az, de = samples[i].elevation_deg - el;
    all.emplace_back(da * da + de * de, int(i));
  }
  std::sort(all.begin(), all.end());
  all.resize(std::min<std::size_t>(all.size(), std::size_t(k)));
  return all;
}

TEST(AngularBins, NearestEqualsABruteForceSearch) {
  std::mt19937 random(7);
  auto az = kRandomAzimuth;
  auto el = kRandomElevation;
  const std::vector<mm::AngularSample> samples = randomSamples(random);
  for (double bin : {0.15, 0.5, 3.0}) {
    const mm::AngularBins bins(samples, bin);
    std::vector<std::pair<double, int>> found;
    for (int q = 0; q < 300; ++q) {
      // Inside and outside the samples' box, with and without a start reach.
      const double qaz = 1.3 * az(random), qel = 1.3 * el(random);
      const int k = 1 + q % 12;
      bins.nearest(qaz, qel, k, found, q % 2 ? 0.0 : 0.05 * (q % 7));
      const std::vector<std::pair<double, int>> all = bruteForceNearest(samples, qaz, qel, k);
      ASSERT_EQ(found, all) << "bin " << bin << " query " << q;
    }
  }
}

TEST(AngularBins, NearestOnScanLinesFromAboveAndOnTiesEqualsABruteForceSearch) {
  // LiDAR-like scan lines on a regular grid (many exactly equal distances, decided by index, in
  // different bin rows and columns), queried from far above the top line (the sky: the walk stops
  // after the first rows), from below, and at points midway between lines and columns.
  std::vector<mm::AngularSample> samples;
  for (int line = 0; line < 8; ++line) {
    for (int c = 0; c < 200; ++c)
      samples.push_back({-20.0f + 0.25f * c, -10.0f + 1.5f * line, 10.0f});
  }
  samples.push_back(samples[333]);  // a duplicate direction
  std::mt19937 random(3);
  std::uniform_int_distribution<int> column(0, 200);
  for (double bin : {0.5, 1.0, 4.0}) {
    const mm::AngularBins bins(samples, bin);
    std::vector<std::pair<double, int>> found;
    for (int q = 0; q < 240; ++q) {
      const double qaz = -20.0 + 0.125 * column(random);
      const double qel =
          q % 3 == 0 ? 3.0 + 0.37 * (q % 40) : (q % 3 == 1 ? -12.0 : -9.25 + 0.75 * (q % 12));
      const int k = 1 + q % 9;
      bins.nearest(qaz, qel, k, found, q % 2 ? 0.0 : 0.1 * (q % 5));
      const std::vector<std::pair<double, int>> all = bruteForceNearest(samples, qaz, qel, k);
      ASSERT_EQ(found, all) << "bin " << bin << " query " << q << " at " << qaz << ", " << qel;
    }
  }
}

TEST(RegionNearest, AnswersEqualTheBinSearchEverywhereInTheRegion) {
  std::mt19937 random(11);
  auto az = kRandomAzimuth;
  auto el = kRandomElevation;
  std::vector<mm::AngularSample> samples = randomSamples(random);
  // Ties: a few samples at the same angles (equal distances, decided by index).
  for (int i = 0; i < 40; ++i)
    samples.push_back(samples[i * 7]);
  const mm::AngularBins bins(samples, 0.15);
  const mm::AngularBins gather_bins(samples, 0.5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  mm::RegionNearest region;
  std::vector<std::pair<double, int>> found, exact;
  for (int r = 0; r < 60; ++r) {
    const std::size_t k = 1 + r % 10;
    const double caz = 1.1 * az(random), cel = 1.1 * el(random);
    const double extent = 0.05 + 0.05 * (r % 9);
    // Guesses far too small, about right and far too large: only the cost may differ.
    const double guess = r % 3 == 0 ? 1e-3 : (r % 3 == 1 ? 0.3 : 20.0);
    const double kth = region.gatherAround(gather_bins, caz, cel, extent, k, guess);
    bins.nearest(caz, cel, static_cast<int>(k), exact);
    ASSERT_EQ(exact.size(), k);
    EXPECT_DOUBLE_EQ(kth * kth, exact.back().first) << "region " << r;
    // A walk of neighbouring queries (each bounded by the previous answer) and jumps, all within
    // the extent.
    double qaz = caz, qel = cel;
    for (int q = 0; q < 40; ++q) {
      if (q % 10 == 0) {
        qaz = caz + extent * unit(random) / std::sqrt(2.0);
        qel = cel + extent * unit(random) / std::sqrt(2.0);
      } else {
        qaz = std::clamp(qaz + 0.01 * unit(random), caz - extent / 1.5, caz + extent / 1.5);
        qel = std::clamp(qel + 0.01 * unit(random), cel - extent / 1.5, cel + extent / 1.5);
      }
      region.nearest(qaz, qel, k, found);
      bins.nearest(qaz, qel, static_cast<int>(k), exact);
      ASSERT_EQ(found, exact) << "region " << r << " query " << q;
    }
  }
}

TEST(RegionNearest, KChangingBetweenQueriesOfOneRegionStillGivesTheExactAnswer) {
  // Each query starts from the previous answer; a different k, or a query far from the last one,
  // must only cost time.
  std::mt19937 random(5);
  std::vector<mm::AngularSample> samples = randomSamples(random);
  for (int i = 0; i < 20; ++i)
    samples.push_back(samples[i * 3]);  // ties
  const mm::AngularBins bins(samples, 0.15);
  const mm::AngularBins gather_bins(samples, 0.5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  mm::RegionNearest region;
  std::vector<std::pair<double, int>> found, exact;
  const double caz = 0.3, cel = -0.2, extent = 0.3;
  region.gatherAround(gather_bins, caz, cel, extent, 10, 0.2);
  for (int q = 0; q < 200; ++q) {
    const std::size_t k = 1 + (q * 7) % 10;
    const double qaz = caz + extent * unit(random) / std::sqrt(2.0);
    const double qel = cel + extent * unit(random) / std::sqrt(2.0);
    region.nearest(qaz, qel, k, found);
    bins.nearest(qaz, qel, static_cast<int>(k), exact);
    ASSERT_EQ(found, exact) << "query " << q << " k " << k;
  }
}

TEST(RegionNearest, FewerSamplesThanKGathersThemAll) {
  const std::vector<mm::AngularSample> samples = {
      {0.0f, 0.0f, 5.0f}, {3.0f, 1.0f, 6.0f}, {-40.0f, 10.0f, 7.0f}};
  const mm::AngularBins bins(samples, 0.5);
  mm::RegionNearest region;
  region.gatherAround(bins, 1.0, 0.0, 0.2, 8, 0.1);
  EXPECT_EQ(region.size(), samples.size());
  std::vector<std::pair<double, int>> found, exact;
  region.nearest(1.1, 0.1, 8, found);
  bins.nearest(1.1, 0.1, 8, exact);
  EXPECT_EQ(found, exact);
  EXPECT_EQ(found.size(), samples.size());
  const mm::AngularBins none(std::vector<mm::AngularSample>{}, 0.5);
  region.gatherAround(none, 0.0, 0.0, 0.2, 4, 0.1);
  region.nearest(0.0, 0.0, 4, found);
  EXPECT_TRUE(found.empty());
}

TEST(AngularTriangulation, BarycentricRowEqualsThePerPixelTest) {
  // A triangle and a row of pixel angles across it, with a NaN angle (a pixel beyond a lens
  // model's range): the row test gives each pixel the bits and the verdict of the scalar test.
  mm::AngularTriangle t{};
  const double az[3] = {-1.0, 2.5, 0.3}, el[3] = {-0.7, 0.1, 1.9};
  for (int i = 0; i < 3; ++i) {
    t.az[i] = az[i];
    t.el[i] = el[i];
  }
  t.det = (t.az[1] - t.az[0]) * (t.el[2] - t.el[0]) - (t.az[2] - t.az[0]) * (t.el[1] - t.el[0]);
  std::vector<float> row_az, row_el;
  for (int i = 0; i < 37; ++i) {
    row_az.push_back(-1.5f + 0.11f * float(i));
    row_el.push_back(0.2f + 0.01f * float(i));
  }
  row_az[5] = std::numeric_limits<float>::quiet_NaN();
  const int n = static_cast<int>(row_az.size());
  // The row test works in whole blocks: inputs readable and outputs writable that far.
  row_az.resize(std::size_t(n) + mm::kBarycentricBlock, 0.0f);
  row_el.resize(std::size_t(n) + mm::kBarycentricBlock, 0.0f);
  std::vector<double> l1s(n + mm::kBarycentricBlock), l2s(n + mm::kBarycentricBlock);
  std::vector<std::uint8_t> inside(n + mm::kBarycentricBlock);
  mm::barycentricRow(t, row_az.data(), row_el.data(), n, l1s.data(), l2s.data(), inside.data());
  int inside_count = 0;
  for (int i = 0; i < n; ++i) {
    const double inv_det = 1.0 / t.det;
    const double pa = double(row_az[i]) - t.az[0], pe = double(row_el[i]) - t.el[0];
    const double l1 = (pa * (t.el[2] - t.el[0]) - (t.az[2] - t.az[0]) * pe) * inv_det;
    const double l2 = ((t.az[1] - t.az[0]) * pe - pa * (t.el[1] - t.el[0])) * inv_det;
    const double l0 = 1.0 - l1 - l2;
    const bool expected = !(l0 < -1e-7 || l1 < -1e-7 || l2 < -1e-7);
    EXPECT_EQ(bool(inside[i]), expected) << i;
    if (!std::isnan(l1)) {
      EXPECT_EQ(l1s[i], l1) << i;
      EXPECT_EQ(l2s[i], l2) << i;
    }
    inside_count += inside[i] && !std::isnan(l1);
  }
  EXPECT_TRUE(inside[5]);      // NaN passes, as it does the scalar test
  EXPECT_GT(inside_count, 5);  // the row crosses the triangle
  EXPECT_LT(inside_count, n - 5);
}

}  // namespace

namespace {

TEST(AngularTriangulation, RasterisedRowsEqualAPerPixelScanOfEveryTriangle) {
  // Random samples over more than the view, so that boxes reach the grid's last row and column
  // (the row test reads whole blocks past a box, into the grid's padding): every pixel gets the
  // first triangle (in order) whose scalar test it passes inside the triangle's box, with that
  // test's coordinates.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> az(-34.0f, 34.0f), el(-26.0f, 26.0f), z(2.0f, 40.0f);
  std::vector<mm::AngularSample> samples(300);
  for (auto& s : samples)
    s = {az(rng), el(rng), z(rng)};
  const mm::StrideGrid grid{{47, 61}, 1};  // no multiple of the row test's block
  const mm::PixelAngleGrid angles(kCamera, grid);
  const std::vector<mm::AngularTriangle> triangles = mm::triangulateSamples(samples, angles);
  ASSERT_GT(triangles.size(), 100u);
  mm::ThreadPool pool(2);
  std::vector<std::uint8_t> filled;
  std::vector<int> winner(grid.size(), -1);
  std::vector<double> l1_at(grid.size(), 0.0);
  mm::rasterizeTriangles(triangles, angles, pool, filled,
                         [&](const mm::AngularTriangle& t, double, double l1, double,
                             std::size_t pixel, float, float) {
                           winner[pixel] = static_cast<int>(&t - triangles.data());
                           l1_at[pixel] = l1;
                           return true;
                         });
  int filled_count = 0;
  for (int r = 0; r < grid.rows(); ++r) {
    for (int c = 0; c < grid.cols(); ++c) {
      const std::size_t pixel = std::size_t(r) * grid.cols() + c;
      int expected = -1;
      double expected_l1 = 0.0;
      for (std::size_t i = 0; i < triangles.size() && expected < 0; ++i) {
        const mm::AngularTriangle& t = triangles[i];
        if (r < t.row0 || r > t.row1 || c < t.col0 || c > t.col1) continue;
        const double pa = double(angles.azimuthRow(r)[c]) - t.az[0];
        const double pe = double(angles.elevationRow(r)[c]) - t.el[0];
        const double inv_det = 1.0 / t.det;
        const double l1 = (pa * (t.el[2] - t.el[0]) - (t.az[2] - t.az[0]) * pe) * inv_det;
        const double l2 = ((t.az[1] - t.az[0]) * pe - pa * (t.el[1] - t.el[0])) * inv_det;
        if (!(1.0 - l1 - l2 < -1e-7 || l1 < -1e-7 || l2 < -1e-7)) {
          expected = static_cast<int>(i);
          expected_l1 = l1;
        }
      }
      ASSERT_EQ(winner[pixel], expected) << r << " " << c;
      EXPECT_EQ(bool(filled[pixel]), expected >= 0);
      if (expected >= 0) {
        EXPECT_EQ(l1_at[pixel], expected_l1);
      }
      filled_count += expected >= 0;
    }
  }
  EXPECT_GT(filled_count, grid.size() / 2);
}

}  // namespace
