// The baseline models on analytic scenes: nearest is exact at a sample, linear is exact wherever
// depth is affine in the angles and silent outside the hull, constant is the median with the
// sample variance, ipbasic fills holes; all go through DepthCompleter like the GP models.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/models/distance_variance.hpp"
#include "multimodal_nvs/core/depth/models/model_registry.hpp"
#include "multimodal_nvs/core/depth/models/nearest_model.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/retention.hpp"

namespace mm = multimodal_nvs;
using mm::test::pointOnPixelRay;
using mm::test::smallCamera;
using mm::test::smallImage;

namespace {

constexpr double kPi = 3.14159265358979323846;

mm::DepthMap run(const std::vector<Eigen::Vector3d>& points, mm::DepthModel model, int stride = 1,
                 double retain = 100.0) {
  mm::DepthCompletionParams params;
  params.model = model;
  params.retain_percent = retain;
  params.threads = 2;
  mm::DepthCompleter completer(2);
  return completer.complete(points, smallCamera(), mm::StrideGrid{smallImage(), stride}, params);
}

std::size_t at(const mm::DepthMap& map, int u, int v) {
  return static_cast<std::size_t>(v / map.grid.stride) * map.grid.cols() + u / map.grid.stride;
}

/// Depth as an affine function of the angles (degrees): linear interpolation must reproduce it.
double affineDepth(double az, double el) {
  return 20.0 + 0.4 * az - 0.3 * el;
}

void anglesOf(const Eigen::Vector3d& p, double* az, double* el) {
  *az = std::atan2(p.x(), p.z()) * 180.0 / kPi;
  *el = std::atan2(-p.y(), std::hypot(p.x(), p.z())) * 180.0 / kPi;
}

}  // namespace

TEST(Baselines, NamesRoundTrip) {
  for (const char* name : {"nearest", "linear", "ipbasic", "constant"}) {
    const mm::DepthModel model = mm::parseDepthModel(name);
    EXPECT_STREQ(mm::toString(model), name);
    EXPECT_TRUE(mm::isBaseline(model));
  }
  EXPECT_FALSE(mm::isBaseline(mm::DepthModel::kLocalGpMle));
  EXPECT_FALSE(mm::isBaseline(mm::DepthModel::kKernel));
  EXPECT_THROW(mm::parseDepthModel("nearest_neighbour"), mm::InputError);
}

TEST(Baselines, AngularToPixelInvertsTheProjection) {
  const auto k = smallCamera();
  const Eigen::Vector3d p = pointOnPixelRay(k, 17.25, 93.5, 12.0);
  double az = 0, el = 0, u = 0, v = 0;
  anglesOf(p, &az, &el);
  ASSERT_TRUE(mm::angularToPixel(k, az, el, &u, &v));
  EXPECT_NEAR(u, 17.25, 1e-9);
  EXPECT_NEAR(v, 93.5, 1e-9);
  EXPECT_FALSE(mm::angularToPixel(k, 90.0, 0.0, &u, &v));
}

TEST(Baselines, NearestIsExactAtASampleAndEverywhereDefined) {
  const auto k = smallCamera();
  const std::vector<Eigen::Vector3d> points = {pointOnPixelRay(k, 40, 30, 7.0),
                                               pointOnPixelRay(k, 120, 90, 15.0),
                                               {0.0, 0.0, -5.0}};  // behind: never used
  const mm::DepthMap map = run(points, mm::DepthModel::kNearest);
  EXPECT_EQ(map.stats.predicted, map.stats.pixels);
  EXPECT_FLOAT_EQ(map.depth[at(map, 40, 30)], 7.0f);
  EXPECT_FLOAT_EQ(map.depth[at(map, 120, 90)], 15.0f);
  EXPECT_FLOAT_EQ(map.depth[at(map, 0, 0)], 7.0f);  // nearer to the first
  EXPECT_FLOAT_EQ(map.depth[at(map, 159, 119)], 15.0f);
  for (float d : map.depth)
    EXPECT_GT(d, 0.0f);
  // Variance: the noise at the sample, growing with the angular distance.
  mm::DepthCompletionParams params;
  EXPECT_NEAR(map.variance[at(map, 40, 30)], params.gp.noise * params.gp.noise, 1e-3);
  EXPECT_LT(map.variance[at(map, 40, 30)], map.variance[at(map, 44, 30)]);
  EXPECT_LT(map.variance[at(map, 44, 30)], map.variance[at(map, 50, 30)]);
  EXPECT_NEAR(mm::distanceVariance(0.75, params), 0.25 + 625.0, 1e-9);
}

namespace {

/// Every pixel of `map` holds the depth of the angularly nearest of `points` (the first on a tie).
void expectNearestIsBruteForce(const mm::DepthMap& map, const std::vector<Eigen::Vector3d>& points,
                               const mm::PinholeIntrinsics& k) {
  const std::vector<mm::AngularSample> samples = mm::toAngularSamples(points);
  const mm::PixelAngleGrid angles(k, map.grid);
  for (int r = 0; r < map.grid.rows(); ++r) {
    for (int c = 0; c < map.grid.cols(); ++c) {
      const float az = angles.azimuthRow(r)[c], el = angles.elevationRow(r)[c];
      float best = INFINITY;
      float depth = 0;
      for (const auto& s : samples) {
        const float da = s.azimuth_deg - az, de = s.elevation_deg - el;
        if (da * da + de * de < best) {
          best = da * da + de * de;
          depth = s.depth;
        }
      }
      ASSERT_EQ(map.depth[std::size_t(r) * map.grid.cols() + c], depth) << r << " " << c;
    }
  }
}

}  // namespace

namespace {
/// `count` points 2-42 m away on the rays of random pixels in [u0, u0 + width) x [v0, v0 + height)
/// of the small camera (seeded: the same points every run).
std::vector<Eigen::Vector3d> randomPoints(unsigned seed, int count, double u0, double width,
                                          double v0, double height) {
  std::srand(seed);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    const double u = u0 + width * std::rand() / RAND_MAX, v = v0 + height * std::rand() / RAND_MAX;
    points.push_back(pointOnPixelRay(smallCamera(), u, v, 2.0 + 40.0 * std::rand() / RAND_MAX));
  }
  return points;
}
}  // namespace

TEST(Baselines, NearestMatchesBruteForceOnRandomScenes) {
  const auto k = smallCamera();
  // Also points outside the image, so some pixels' nearest samples lie beyond the border.
  const std::vector<Eigen::Vector3d> points = randomPoints(7, 300, -80, 320, -60, 240);
  const mm::DepthMap map = run(points, mm::DepthModel::kNearest, 3);
  expectNearestIsBruteForce(map, points, k);
}

// The index another model reads (image_guided's surface prior) names the sample whose depth the
// nearest model writes, pixel by pixel, ties included; without samples every index is -1.
TEST(Baselines, NearestSampleIndexNamesTheSampleOfTheNearestDepth) {
  const auto k = smallCamera();
  std::vector<Eigen::Vector3d> points = randomPoints(5, 200, -40, 240, -30, 180);
  points.push_back(3.0 * points[9]);  // a tie: the lower index wins in both
  const mm::StrideGrid grid{smallImage(), 2};
  const mm::PixelAngleGrid angles(k, grid);
  const std::vector<mm::AngularSample> samples = mm::usableSamples(mm::toAngularSamples(points));
  mm::ThreadPool pool(2);
  const std::vector<int> index = mm::nearestSampleIndex(samples, angles, pool);
  const mm::DepthMap map = run(points, mm::DepthModel::kNearest, 2);
  ASSERT_EQ(index.size(), map.depth.size());
  for (std::size_t i = 0; i < index.size(); ++i) {
    ASSERT_GE(index[i], 0) << i;
    ASSERT_EQ(samples[index[i]].depth, map.depth[i]) << i;
  }
  const std::vector<int> none = mm::nearestSampleIndex({}, angles, pool);
  ASSERT_EQ(none.size(), index.size());
  for (int i : none)
    ASSERT_EQ(i, -1);
}

// A narrow camera whose returns lie in the bottom rows only (a LiDAR's view): the blocks far above
// them take the one-set-per-large-block path, which must stay exact (ties: the lower index).
TEST(Baselines, NearestMatchesBruteForceFarFromTheData) {
  const mm::PinholeIntrinsics k{1000.0, 1000.0, 80.0, 150.0};
  const mm::ImageSize image{300, 160};
  std::srand(11);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 400; ++i) {
    const double u = -10 + 180.0 * std::rand() / RAND_MAX, v = 260 + 40.0 * std::rand() / RAND_MAX;
    points.push_back(pointOnPixelRay(k, u, v, 5.0 + 30.0 * std::rand() / RAND_MAX));
  }
  points.push_back(2.0 * points[17]);  // same angles (exact scaling): the lower index must win
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kNearest;
  mm::DepthCompleter completer(2);
  const mm::DepthMap map = completer.complete(points, k, mm::StrideGrid{image, 1}, params);
  expectNearestIsBruteForce(map, points, k);
}

TEST(Baselines, LinearIsExactForDepthAffineInTheAngles) {
  const auto k = smallCamera();
  std::vector<Eigen::Vector3d> points;
  for (int v = 20; v <= 100; v += 10) {
    for (int u = 20; u <= 140; u += 12) {
      double az = 0, el = 0;
      anglesOf(pointOnPixelRay(k, u + 0.3 * (v % 20), v, 1.0), &az, &el);
      points.push_back(pointOnPixelRay(k, u + 0.3 * (v % 20), v, affineDepth(az, el)));
    }
  }
  const mm::DepthMap map = run(points, mm::DepthModel::kLinear);
  const mm::PixelAngleGrid angles(k, map.grid);
  long long inside = 0;
  for (int r = 0; r < map.grid.rows(); ++r) {
    for (int c = 0; c < map.grid.cols(); ++c) {
      const std::size_t i = std::size_t(r) * map.grid.cols() + c;
      if (!map.valid[i]) continue;
      ++inside;
      ASSERT_NEAR(map.depth[i], affineDepth(angles.azimuthRow(r)[c], angles.elevationRow(r)[c]),
                  2e-4)
          << r << " " << c;
    }
  }
  // The hull spans pixels 20..140 x 20..100: the interior is covered, the corners are not.
  EXPECT_GT(inside, 110 * 75);
  EXPECT_LT(inside, 125 * 85);
  EXPECT_TRUE(map.valid[at(map, 80, 60)]);
  EXPECT_FALSE(map.valid[at(map, 5, 5)]);
  EXPECT_EQ(map.depth[at(map, 5, 5)], -1.0f);
  EXPECT_TRUE(std::isinf(map.variance[at(map, 5, 5)]));
}

TEST(Baselines, LinearOnAFrontoParallelPlaneIsExactWithZeroVariance) {
  const auto k = smallCamera();
  const mm::DepthMap map =
      run(mm::test::planePoints(k, smallImage(), 12.5, 16), mm::DepthModel::kLinear, 2);
  ASSERT_GT(map.stats.kept, 0);
  for (std::size_t i = 0; i < map.depth.size(); ++i) {
    if (!map.valid[i]) continue;
    ASSERT_NEAR(map.depth[i], 12.5f, 1e-4);
    ASSERT_NEAR(map.variance[i], 0.0f, 1e-6);
  }
}

TEST(Baselines, LinearNeedsThreeSamples) {
  const auto k = smallCamera();
  const mm::DepthMap map =
      run({pointOnPixelRay(k, 10, 10, 5), pointOnPixelRay(k, 100, 90, 6)}, mm::DepthModel::kLinear);
  EXPECT_EQ(map.stats.predicted, 0);
}

TEST(Baselines, ConstantIsTheMedianOfTheSamplesInViewWithTheirSampleVariance) {
  const auto k = smallCamera();
  const std::vector<Eigen::Vector3d> points = {
      pointOnPixelRay(k, 10, 10, 5.0),
      pointOnPixelRay(k, 50, 20, 10.0),
      pointOnPixelRay(k, 90, 70, 20.0),
      pointOnPixelRay(k, 150, 110, 40.0),
      pointOnPixelRay(k, -300, 60, 100.0),  // outside the image
      {1.0, 0.0, -3.0}};                    // behind the camera
  const mm::DepthMap map = run(points, mm::DepthModel::kConstant, 4);
  EXPECT_EQ(map.stats.kept, map.stats.pixels);
  const double mean = (5 + 10 + 20 + 40) / 4.0;
  const double var = ((5 - mean) * (5 - mean) + (10 - mean) * (10 - mean) +
                      (20 - mean) * (20 - mean) + (40 - mean) * (40 - mean)) /
                     3.0;
  for (std::size_t i = 0; i < map.depth.size(); ++i) {
    ASSERT_FLOAT_EQ(map.depth[i], 15.0f);
    ASSERT_FLOAT_EQ(map.variance[i], static_cast<float>(var));
  }
}

TEST(Baselines, IpBasicFillsHolesOfAScanPattern) {
  const auto k = smallCamera();
  // LiDAR-like scan lines every 4 rows, a return every 3 columns, on a plane at 9 m with a 20x12
  // pixel hole, and nothing above row 40.
  std::vector<Eigen::Vector3d> points;
  for (int v = 40; v < 120; v += 4) {
    for (int u = 0; u < 160; u += 3) {
      if (u >= 70 && u < 90 && v >= 60 && v < 72) continue;
      points.push_back(pointOnPixelRay(k, u, v, 9.0));
    }
  }
  const mm::DepthMap map = run(points, mm::DepthModel::kIpBasic);
  EXPECT_EQ(map.stats.predicted, map.stats.pixels);  // hole, gaps and the rows above are filled
  for (std::size_t i = 0; i < map.depth.size(); ++i)
    ASSERT_NEAR(map.depth[i], 9.0f, 1e-3);
  // Farther from a return, larger variance.
  EXPECT_LT(map.variance[at(map, 60, 40)], map.variance[at(map, 80, 66)]);
  EXPECT_LT(map.variance[at(map, 80, 66)], map.variance[at(map, 80, 5)]);
}

TEST(Baselines, IpBasicKeepsTheNearerSurfaceAtAnEdge) {
  const auto k = smallCamera();
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < 120; v += 3) {
    for (int u = 0; u < 160; u += 3)
      points.push_back(pointOnPixelRay(k, u, v, u < 80 ? 5.0 : 30.0));
  }
  const mm::DepthMap map = run(points, mm::DepthModel::kIpBasic);
  EXPECT_NEAR(map.depth[at(map, 30, 60)], 5.0f, 1e-3);
  EXPECT_NEAR(map.depth[at(map, 130, 60)], 30.0f, 1e-3);
}

TEST(Baselines, NoUsableSampleMeansNoPrediction) {
  const std::vector<Eigen::Vector3d> behind = {{0.0, 0.0, -4.0}, {1.0, 0.5, -9.0}};
  for (const char* name : {"nearest", "linear", "ipbasic", "constant"}) {
    const mm::DepthMap empty = run({}, mm::parseDepthModel(name), 4);
    EXPECT_EQ(empty.stats.predicted, 0) << name;
    const mm::DepthMap map = run(behind, mm::parseDepthModel(name), 4);
    EXPECT_EQ(map.stats.predicted, 0) << name;
    EXPECT_EQ(map.stats.kept, 0) << name;
  }
}

TEST(Baselines, RetentionKeepsTheNearestPixelsOfTheNearestBaseline) {
  const auto k = smallCamera();
  const mm::DepthMap map = run({pointOnPixelRay(k, 80, 60, 10.0)}, mm::DepthModel::kNearest, 1, 10);
  EXPECT_EQ(map.stats.kept, mm::retentionCount(10, map.stats.pixels));
  EXPECT_TRUE(map.valid[at(map, 80, 60)]);
  EXPECT_FALSE(map.valid[at(map, 0, 0)]);
}
