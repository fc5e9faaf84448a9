// The ground_gp model (issue 8): ground-plane prior, nearest-surface prior, residual GP, and a
// variance that grows away from the samples.
#include <gtest/gtest.h>

#include <cmath>

#include "multimodal_nvs/core/depth_completion.hpp"
#include "multimodal_nvs/core/errors.hpp"
#include "multimodal_nvs/core/ground_prior.hpp"
#include "scene_fixtures.hpp"

namespace mm = multimodal_nvs;
using mm::test::pointOnPixelRay;
using mm::test::smallCamera;
using mm::test::smallImage;

TEST(GroundPrior, LevelCameraSeesTheGroundAtHeightOverSlope) {
  Eigen::Matrix4d level = Eigen::Matrix4d::Identity();
  // Camera axes (x right, y down, z forward) in a z-up world: x -> -y... use the VoD convention
  // world = (z_cam, -x_cam, -y_cam): rows of the rotation map camera to world.
  level.block<3, 3>(0, 0) << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  level(2, 3) = 1.5;
  const mm::GroundPlane plane = mm::GroundPlane::fromCameraToWorld(level);
  EXPECT_NEAR(plane.up.y(), -1.0, 1e-12);
  EXPECT_NEAR(plane.height, 1.5, 1e-12);
  EXPECT_NEAR(plane.depthAlong(0.3, 0.1), 15.0, 1e-9);  // z = h / y
  EXPECT_TRUE(std::isinf(plane.depthAlong(0.0, -0.1)));  // above the horizon
}

TEST(GroundPrior, PixelPriorIsGroundBelowTheHorizonAndFarAbove) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::GroundPlane plane;
  plane.height = 2.0;
  const auto prior = mm::groundPriorDepth(angles, plane, 50.0);
  EXPECT_NEAR(prior[std::size_t(100) * 160 + 7], 2.0 / ((100 - 60) / 100.0), 1e-4);
  EXPECT_EQ(prior[std::size_t(10) * 160 + 7], 50.0f);
}

TEST(GroundPrior, NearestSurfaceTakesTheRankedDepthAmongTheNearestSamples) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  // A near return in front of three far ones around the same direction.
  const auto samples = mm::toAngularSamples({pointOnPixelRay(smallCamera(), 80, 60, 5.0),
                                             pointOnPixelRay(smallCamera(), 81, 60, 30.0),
                                             pointOnPixelRay(smallCamera(), 80, 61, 31.0),
                                             pointOnPixelRay(smallCamera(), 79, 60, 32.0)});
  const auto first = mm::nearestSurfaceDepth(samples, angles, 4, 1, 1, pool);
  const auto second = mm::nearestSurfaceDepth(samples, angles, 4, 2, 1, pool);
  const std::size_t centre = std::size_t(60) * 160 + 80;
  EXPECT_NEAR(first.depth[centre], 5.0, 1e-4);
  EXPECT_NEAR(second.depth[centre], 30.0, 1e-3);
  EXPECT_LT(first.distance_deg[centre], 1e-3);
  EXPECT_GT(first.distance_deg[std::size_t(5) * 160 + 5], 20.0);
  // A coarse lattice interpolates but keeps exact values at its nodes.
  const auto coarse = mm::nearestSurfaceDepth(samples, angles, 4, 1, 8, pool);
  EXPECT_NEAR(coarse.depth[std::size_t(56) * 160 + 80], first.depth[std::size_t(56) * 160 + 80], 1e-4);
}

TEST(GroundGp, RecoversAFlatRoadAndItsVarianceGrowsAwayFromSamples) {
  // Samples on the ground plane 1.3 m below a level camera, only in the lower-left quadrant.
  std::vector<Eigen::Vector3d> points;
  for (int v = 70; v < 120; v += 5) {
    for (int u = 0; u < 80; u += 5) {
      const double z = 1.3 / ((v - 60) / 100.0);
      points.push_back(pointOnPixelRay(smallCamera(), u, v, z));
    }
  }
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  mm::DepthCompleter completer(2);
  const auto map = completer.complete(points, smallCamera(), {smallImage(), 1}, params);
  for (int v : {75, 90, 110}) {
    for (int u : {10, 70, 150}) {  // the right half has no sample: the ground prior covers it
      const double truth = 1.3 / ((v - 60) / 100.0);
      EXPECT_NEAR(map.depth[std::size_t(v) * 160 + u], truth, 0.05 * truth) << v << "," << u;
    }
  }
  const float near = map.variance[std::size_t(90) * 160 + 10];
  const float far = map.variance[std::size_t(90) * 160 + 150];
  EXPECT_GT(near, 0.0f);
  EXPECT_GT(far, near);
  for (float v : map.variance) ASSERT_TRUE(std::isfinite(v));
}

TEST(GroundGp, NearReturnsWinOverFarOnes) {
  // An object at 6 m seen by a few returns, with multipath returns at 40 m around it.
  std::vector<Eigen::Vector3d> points;
  for (int u = 60; u <= 100; u += 10) {
    points.push_back(pointOnPixelRay(smallCamera(), u, 50, 6.0));
    points.push_back(pointOnPixelRay(smallCamera(), u + 3, 52, 40.0));
  }
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  mm::DepthCompleter completer(1);
  const auto map = completer.complete(points, smallCamera(), {smallImage(), 1}, params);
  EXPECT_NEAR(map.depth[std::size_t(50) * 160 + 80], 6.0, 1.0);
}

TEST(GroundGp, InvalidParametersAreRejected) {
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  params.ground.surface_rank = 9;
  mm::DepthCompleter completer(1);
  EXPECT_THROW(completer.complete({}, smallCamera(), {smallImage(), 1}, params), mm::InputError);
  params.ground = {};
  params.ground.camera_height = 0.0;
  EXPECT_THROW(completer.complete({}, smallCamera(), {smallImage(), 1}, params), mm::InputError);
}
