// Analytic tests of depth completion: plane, step edge, a point on a pixel ray, no
// points, duplicates, points behind the camera, non-finite coordinates, variance behaviour,
// retention, stride grid, thread independence.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"

namespace mm = multimodal_nvs;
using mm::test::planePoints;
using mm::test::pointOnPixelRay;
using mm::test::smallCamera;
using mm::test::smallImage;

namespace {

mm::DepthMap run(const std::vector<Eigen::Vector3d>& points, mm::DepthCompletionParams params = {},
                 int stride = 1) {
  mm::DepthCompleter completer(params.threads);
  return completer.complete(points, smallCamera(), {smallImage(), stride}, params);
}

std::size_t at(const mm::DepthMap& m, int row, int col) {
  return std::size_t(row) * m.grid.cols() + col;
}

const double kA2 = 625.0, kNoise2 = 0.25;

}  // namespace

TEST(DepthCompletion, OnePointOnAPixelRayGivesTheAnalyticPosterior) {
  mm::DepthCompletionParams params;
  params.shift = mm::DepthShift::parse("none");
  const auto map = run({pointOnPixelRay(smallCamera(), 40, 30, 12.0)}, params);
  // k* = a^2 at zero distance: mean = a^2/(a^2+s^2) z, var = a^2+s^2 - a^4/(a^2+s^2).
  EXPECT_NEAR(map.depth[at(map, 30, 40)], kA2 / (kA2 + kNoise2) * 12.0, 1e-4);
  EXPECT_NEAR(map.variance[at(map, 30, 40)], kA2 + kNoise2 - kA2 * kA2 / (kA2 + kNoise2), 1e-3);
}

TEST(DepthCompletion, MedianShiftMakesASinglePointExactAtItsPixel) {
  const auto map = run({pointOnPixelRay(smallCamera(), 40, 30, 12.0)});
  EXPECT_NEAR(map.stats.shift, 12.0, 1e-6);
  EXPECT_NEAR(map.depth[at(map, 30, 40)], 12.0, 1e-5);
}

TEST(DepthCompletion, NoPointsGivesThePriorEverywhere) {
  const auto gp = run({});
  for (std::size_t i = 0; i < gp.depth.size(); ++i) {
    ASSERT_EQ(gp.depth[i], 0.0f);  // shift of an empty scan is 0
    ASSERT_EQ(gp.variance[i], 625.0f);
  }
  mm::DepthCompletionParams kernel;
  kernel.model = mm::DepthModel::kKernel;
  const auto kr = run({}, kernel);
  for (std::size_t i = 0; i < kr.depth.size(); ++i) {
    ASSERT_EQ(kr.depth[i], -1.0f);
    ASSERT_TRUE(std::isinf(kr.variance[i]));
    ASSERT_EQ(kr.valid[i], 0);
  }
  EXPECT_EQ(kr.stats.predicted, 0);
}

TEST(DepthCompletion, PlaneIsRecoveredAndVarianceIsSmallInside) {
  // One point every 3 px: every pixel has several within the 2 deg (~3.5 px) radius.
  const auto map = run(planePoints(smallCamera(), smallImage(), 8.0, 3));
  for (int r = 10; r < 110; r += 7) {
    for (int c = 10; c < 150; c += 7) {
      ASSERT_NEAR(map.depth[at(map, r, c)], 8.0, 0.05) << r << "," << c;
      ASSERT_LT(map.variance[at(map, r, c)], 1.0);
    }
  }
}

TEST(DepthCompletion, StepEdgeKeepsBothSidesAwayFromTheEdge) {
  std::vector<Eigen::Vector3d> points;
  for (int v = 1; v < 120; v += 2) {
    for (int u = 1; u < 160; u += 2)
      points.push_back(pointOnPixelRay(smallCamera(), u, v, u < 80 ? 5.0 : 20.0));
  }
  const auto map = run(points);  // 2 deg ~ 3.5 px: pixels 5 px from the edge see one side only
  for (int r = 10; r < 110; r += 10) {
    EXPECT_NEAR(map.depth[at(map, r, 74)], 5.0, 0.05) << r;
    EXPECT_NEAR(map.depth[at(map, r, 85)], 20.0, 0.05) << r;
    // At the edge the neighbourhood straddles both surfaces: in between, and less certain.
    const float edge = map.depth[at(map, r, 80)];
    EXPECT_GT(edge, 5.5f);
    EXPECT_LT(edge, 19.5f);
    EXPECT_GT(map.variance[at(map, r, 80)], map.variance[at(map, r, 74)]);
  }
}

TEST(DepthCompletion, VarianceGrowsAwayFromDataAndEqualsThePriorWithout) {
  const auto map = run({pointOnPixelRay(smallCamera(), 80, 60, 10.0)});
  float previous = -1.0f;
  for (int c = 80; c < 160; ++c) {
    const float v = map.variance[at(map, 60, c)];
    ASSERT_GE(v, previous) << "column " << c;
    previous = v;
  }
  EXPECT_EQ(map.variance[at(map, 60, 159)], 625.0f);  // 45 deg away: no neighbour, prior
  EXPECT_EQ(map.depth[at(map, 5, 5)], 10.0f);         // prior mean = shift = the only depth
}

TEST(DepthCompletion, DuplicatedPointsFollowTheTwoObservationPosterior) {
  const Eigen::Vector3d p = pointOnPixelRay(smallCamera(), 50, 50, 6.0);
  mm::DepthCompletionParams params;
  params.shift = mm::DepthShift::parse("none");
  const auto map = run({p, p}, params);
  // K = a^2 11^T + s^2 I, k* = a^2 1: mean = 2 a^2 y / (2 a^2 + s^2).
  EXPECT_NEAR(map.depth[at(map, 50, 50)], 2 * kA2 * 6.0 / (2 * kA2 + kNoise2), 1e-4);
}

TEST(DepthCompletion, PointsBehindTheCameraChangeNothing) {
  const Eigen::Vector3d front = pointOnPixelRay(smallCamera(), 50, 50, 6.0);
  const auto clean = run({front, pointOnPixelRay(smallCamera(), 90, 40, 9.0)});
  const auto with_behind = run({front, pointOnPixelRay(smallCamera(), 90, 40, 9.0),
                                Eigen::Vector3d(0.5, 0.2, -7.0), Eigen::Vector3d(-3, 1, -0.5)});
  EXPECT_EQ(clean.depth, with_behind.depth);
  EXPECT_EQ(clean.variance, with_behind.variance);
  EXPECT_EQ(with_behind.stats.points_in_view, 2u);
}

TEST(DepthCompletion, NonFinitePointsAreDroppedAndCounted) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Eigen::Vector3d> clean{pointOnPixelRay(smallCamera(), 50, 50, 6.0)};
  auto dirty = clean;
  dirty.emplace_back(nan, 0.0, 5.0);
  dirty.emplace_back(0.0, inf, 5.0);
  dirty.emplace_back(0.0, 0.0, -inf);
  const auto a = run(clean), b = run(dirty);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(b.stats.points_non_finite, 3u);
  EXPECT_EQ(b.stats.points_total, 4u);
}

TEST(DepthCompletion, KernelModelSinglePointHasZeroVarianceAndExactDepth) {
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kKernel;
  const auto map = run({pointOnPixelRay(smallCamera(), 40, 30, 12.0)}, params);
  EXPECT_NEAR(map.depth[at(map, 30, 40)], 12.0, 1e-5);
  EXPECT_EQ(map.variance[at(map, 30, 40)], 0.0f);
  EXPECT_EQ(map.valid[at(map, 0, 159)], 0);  // far away: no prediction
}

TEST(DepthCompletion, RetentionKeepsExactlyTheRequestedCount) {
  mm::DepthCompletionParams params;
  params.retain_percent = 37.5;
  const auto map = run(planePoints(smallCamera(), smallImage(), 8.0, 20), params);
  const long long total = 120 * 160;
  EXPECT_EQ(map.stats.kept, std::llround(0.375 * total));
  long long valid = 0;
  float worst_kept = 0.0f, best_dropped = std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < map.valid.size(); ++i) {
    valid += map.valid[i];
    if (map.valid[i]) worst_kept = std::max(worst_kept, map.variance[i]);
    if (!map.valid[i]) {
      best_dropped = std::min(best_dropped, map.variance[i]);
      ASSERT_EQ(map.depth[i], -1.0f);
    }
  }
  EXPECT_EQ(valid, map.stats.kept);
  EXPECT_LE(worst_kept, best_dropped);
}

TEST(DepthCompletion, RetentionBreaksTiesInRowMajorOrder) {
  mm::DepthCompletionParams params;
  params.retain_percent = 10.0;  // every pixel has the prior variance: pure ties
  const auto map = run({}, params);
  const long long keep = std::llround(0.1 * 120 * 160);
  for (long long i = 0; i < 120 * 160; ++i)
    ASSERT_EQ(map.valid[i], i < keep ? 1 : 0) << i;
}

TEST(DepthCompletion, VarianceThresholdInvalidatesUncertainPixels) {
  mm::DepthCompletionParams params;
  params.var_threshold = 100.0;
  const auto map = run({pointOnPixelRay(smallCamera(), 80, 60, 10.0)}, params);
  EXPECT_EQ(map.valid[at(map, 60, 80)], 1);
  EXPECT_EQ(map.valid[at(map, 0, 0)], 0);
}

TEST(DepthCompletion, StrideGridHasCeilShape) {
  for (int stride : {1, 3, 7, 16}) {
    const auto map = run({pointOnPixelRay(smallCamera(), 80, 60, 10.0)}, {}, stride);
    EXPECT_EQ(map.grid.rows(), (120 + stride - 1) / stride);
    EXPECT_EQ(map.grid.cols(), (160 + stride - 1) / stride);
    EXPECT_EQ(map.depth.size(), std::size_t(map.grid.rows()) * map.grid.cols());
  }
}

TEST(DepthCompletion, ResultsDoNotDependOnTheThreadCount) {
  auto points = planePoints(smallCamera(), smallImage(), 8.0, 13);
  for (std::size_t i = 0; i < points.size(); i += 3)
    points[i].z() += 4.0 * std::sin(double(i));
  for (auto model : {mm::DepthModel::kLocalGpMle, mm::DepthModel::kKernel}) {
    mm::DepthCompletionParams params;
    params.model = model;
    params.threads = 1;
    const auto one = run(points, params);
    for (int threads : {2, 3, 5}) {
      params.threads = threads;
      const auto many = run(points, params);
      ASSERT_EQ(one.depth, many.depth) << threads;
      ASSERT_EQ(one.variance, many.variance) << threads;
    }
  }
}

TEST(DepthCompletion, TileApproximationIsCloseToExactOnAPlane) {
  const auto points = planePoints(smallCamera(), smallImage(), 8.0, 3);
  mm::DepthCompletionParams approx;
  approx.max_neighbors = 16;
  approx.approx_tile = 8;
  const auto exact = run(points), fast = run(points, approx);
  for (std::size_t i = 0; i < exact.depth.size(); i += 17) {
    ASSERT_NEAR(fast.depth[i], exact.depth[i], 0.05) << i;
  }
}

TEST(DepthCompletion, InvalidParametersAndIntrinsicsAreRejected) {
  mm::DepthCompletionParams params;
  params.radius_deg = 0.0;
  EXPECT_THROW(run({}, params), mm::InputError);
  params = {};
  params.retain_percent = 120.0;
  EXPECT_THROW(run({}, params), mm::InputError);
  mm::DepthCompleter completer(1);
  EXPECT_THROW(completer.complete({}, {0.0, 100.0, 80, 60}, {smallImage(), 1}, {}), mm::InputError);
  EXPECT_THROW(completer.complete({}, {-5.0, 100.0, 80, 60}, {smallImage(), 1}, {}),
               mm::InputError);
  EXPECT_THROW(completer.complete({}, smallCamera(), {{0, 160}, 1}, {}), mm::InputError);
}
