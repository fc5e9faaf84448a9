// The Delaunay triangulation of angular samples and the k-nearest search over angular bins, the two
// geometric structures of ground_gp's dense mode and the linear baseline.
#include <gtest/gtest.h>

#include <algorithm>
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
      std::vector<std::pair<double, int>> all;
      for (std::size_t i = 0; i < samples.size(); ++i) {
        const double da = samples[i].azimuth_deg - qaz, de = samples[i].elevation_deg - qel;
        all.emplace_back(da * da + de * de, int(i));
      }
      std::sort(all.begin(), all.end());
      all.resize(k);
      ASSERT_EQ(found, all) << "bin " << bin << " query " << q;
    }
  }
}

TEST(AngularBins, NearestAfterAnEarlierAnswerEqualsNearest) {
  std::mt19937 random(11);
  auto az = kRandomAzimuth;
  auto el = kRandomElevation;
  const std::vector<mm::AngularSample> samples = randomSamples(random);
  const mm::AngularBins bins(samples, 0.15);
  std::uniform_real_distribution<double> step(-0.1, 0.1);
  for (int k : {1, 3, 8}) {
    std::vector<std::pair<double, int>> seeded, exact;
    double qaz = 0.0, qel = -5.0;
    for (int q = 0; q < 600; ++q) {
      // Mostly a walk of small steps (pixels of a row), sometimes a far jump, and now and then an
      // earlier answer that is empty, too short, or from another set of samples (out of range).
      if (q % 50 == 0) {
        qaz = 1.2 * az(random);
        qel = 1.2 * el(random);
      } else {
        qaz += step(random);
        qel += 0.2 * step(random);
      }
      if (q % 97 == 0) seeded.clear();
      if (q % 89 == 0 && !seeded.empty()) seeded.pop_back();
      if (q % 83 == 0 && !seeded.empty()) seeded.front().second = int(samples.size()) + 5;
      // The earlier answer is used when its bound is within twice the start reach (8 nearest: ~1.2
      // deg).
      const double start_reach = q % 3 ? 3.0 : 0.0;
      bins.nearestAfter(qaz, qel, k, seeded, start_reach);
      bins.nearest(qaz, qel, k, exact);
      ASSERT_EQ(seeded, exact) << "k " << k << " query " << q;
    }
  }
}

}  // namespace
