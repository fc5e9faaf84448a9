// The ground_gp model: ground-plane prior, nearest-surface prior, residual GP, and a
// variance that grows away from the samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/depth_shift.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/models/ground_gp_model.hpp"
#include "multimodal_nvs/core/depth/models/model_registry.hpp"
#include "multimodal_nvs/core/depth/models/tiled_local_gp_model.hpp"
#include "multimodal_nvs/core/depth/neighbour_sets.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/eval/depth_metrics.hpp"

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
  EXPECT_NEAR(plane.depthAlong(0.3, 0.1), 15.0, 1e-9);   // z = h / y
  EXPECT_TRUE(std::isinf(plane.depthAlong(0.0, -0.1)));  // above the horizon
}

TEST(GroundPrior, PitchAndRollOfAPoseComeBackInTheParametersConvention) {
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  Eigen::Matrix3d level;
  level << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // camera (x right, y down, z forward) in a z-up world
  // Looking 6.8 deg up (about the camera's x axis), rolled 2 deg about the optical axis.
  const double pitch = 6.8 * M_PI / 180.0, roll = 2.0 * M_PI / 180.0;
  pose.block<3, 3>(0, 0) = level * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()).matrix() *
                           Eigen::AngleAxisd(-roll, Eigen::Vector3d::UnitZ()).matrix();
  pose(2, 3) = 1.45;
  const mm::GroundPlane plane = mm::GroundPlane::fromCameraToWorld(pose);
  EXPECT_NEAR(plane.pitchDeg(), 6.8, 1e-9);
  EXPECT_NEAR(plane.rollDeg(), 2.0, 1e-9);
  EXPECT_GT(plane.up.x(), 0.0);  // positive roll: world up leans towards the image's right
  EXPECT_NEAR(plane.height, 1.45, 1e-12);
  // The ground_pitch_deg parameter's plane (no roll) gives its angle back, and tilts world up
  // towards the optical axis as the pose does.
  mm::GroundPriorParams params;
  params.setPitchDeg(6.8);
  EXPECT_NEAR(params.pitchDeg(), 6.8, 1e-9);
  const mm::GroundPlane from_parameter = mm::givenGroundPlane(params);
  EXPECT_NEAR(from_parameter.pitchDeg(), 6.8, 1e-9);
  EXPECT_NEAR(from_parameter.rollDeg(), 0.0, 1e-12);
  EXPECT_NEAR(from_parameter.up.z(), plane.up.z(), 1e-9);  // a roll keeps the pitch
  EXPECT_NEAR(mm::GroundPlane().pitchDeg(), 0.0, 1e-12);   // the default: a level camera
}

TEST(GroundPrior, APlaneFromItsAnglesGivesThemBackAndItsPatchLiesOnItAhead) {
  const mm::GroundPlane plane = mm::GroundPlane::fromAngles(1.6, -0.8, 2.5);
  EXPECT_NEAR(plane.height, 1.6, 1e-12);
  EXPECT_NEAR(plane.pitchDeg(), -0.8, 1e-9);
  EXPECT_NEAR(plane.rollDeg(), 2.5, 1e-9);
  EXPECT_NEAR(plane.up.norm(), 1.0, 1e-12);
  const auto corners = plane.patchCorners(2.0, 40.0, 10.0);
  for (const Eigen::Vector3d& corner : corners) {
    EXPECT_NEAR(plane.up.dot(corner), -1.6, 1e-9);  // on the road
    EXPECT_GT(corner.z(), 1.9);                     // ahead of the camera
  }
  EXPECT_NEAR((corners[1] - corners[0]).norm(), 20.0, 1e-9);  // 10 m to either side
  EXPECT_NEAR((corners[2] - corners[1]).norm(), 38.0, 1e-9);  // 2 to 40 m ahead
  EXPECT_LT(corners[0].x(), corners[1].x());                  // left, then right
  // A level camera 1.3 m up: the road's rectangle in camera coordinates, y down.
  const auto level = mm::GroundPlane::fromAngles(1.3, 0.0, 0.0).patchCorners(2.0, 40.0, 10.0);
  EXPECT_TRUE(level[0].isApprox(Eigen::Vector3d(-10.0, 1.3, 2.0), 1e-12));
  EXPECT_TRUE(level[2].isApprox(Eigen::Vector3d(10.0, 1.3, 40.0), 1e-12));
}

TEST(GroundPrior, PixelPriorIsGroundBelowTheHorizonAndFarAbove) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::GroundPlane plane;
  plane.height = 2.0;
  const auto prior = mm::groundPriorDepth(angles, plane, 50.0);
  EXPECT_NEAR(prior[std::size_t(100) * 160 + 7], 2.0 / ((100 - 60) / 100.0), 1e-4);
  EXPECT_EQ(prior[std::size_t(10) * 160 + 7], 50.0f);
  // Rows on a pool: the same values.
  mm::ThreadPool pool(2);
  EXPECT_EQ(mm::groundPriorDepth(angles, plane, 50.0, &pool), prior);
  // Row by row (for passes that consume it so) and pixel by pixel: the same values, bit for bit,
  // also with a tilted plane (the columns' terms differ).
  mm::GroundPlane tilted = plane;
  tilted.up = Eigen::Vector3d(0.1, -0.98, 0.05).normalized();
  const auto tilted_prior = mm::groundPriorDepth(angles, tilted, 50.0);
  const mm::GroundPriorRows rows(angles, tilted, 50.0);
  std::vector<float> row(160);
  for (int r = 0; r < angles.grid().rows(); ++r) {
    rows.row(r, row.data());
    for (int c = 0; c < 160; ++c) {
      ASSERT_EQ(row[c], tilted_prior[std::size_t(r) * 160 + c]) << r << ", " << c;
      ASSERT_EQ(row[c], mm::groundPriorDepthAt(angles, tilted, r, c, 50.0)) << r << ", " << c;
    }
  }
}

TEST(GroundPrior, NearestSurfaceTakesTheRankedDepthAmongTheNearestSamples) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  // A near return in front of three far ones around the same direction.
  const auto samples = mm::toAngularSamples(
      {pointOnPixelRay(smallCamera(), 80, 60, 5.0), pointOnPixelRay(smallCamera(), 81, 60, 30.0),
       pointOnPixelRay(smallCamera(), 80, 61, 31.0), pointOnPixelRay(smallCamera(), 79, 60, 32.0)});
  const auto first = mm::nearestSurfaceDepth(samples, angles, 4, 1, 1, pool);
  const auto second = mm::nearestSurfaceDepth(samples, angles, 4, 2, 1, pool);
  const std::size_t centre = std::size_t(60) * 160 + 80;
  EXPECT_NEAR(first.depth[centre], 5.0, 1e-4);
  EXPECT_NEAR(second.depth[centre], 30.0, 1e-3);
  EXPECT_LT(first.distance_deg[centre], 1e-3);
  EXPECT_GT(first.distance_deg[std::size_t(5) * 160 + 5], 20.0);
  // A coarse lattice interpolates but keeps exact values at its nodes.
  const auto coarse = mm::nearestSurfaceDepth(samples, angles, 4, 1, 8, pool);
  EXPECT_NEAR(coarse.depth[std::size_t(56) * 160 + 80], first.depth[std::size_t(56) * 160 + 80],
              1e-4);
}

namespace {
// ground_gp's parameters; `input` forces its dense (LiDAR) or sparse (radar) mode, or leaves it
// automatic.
mm::DepthCompletionParams groundGpParams(
    mm::GroundPriorParams::Input input = mm::GroundPriorParams::Input::kAuto) {
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  params.ground.input = input;
  return params;
}

// One completion of the small camera's full image.
mm::DepthMap completeSmallImage(const std::vector<Eigen::Vector3d>& points,
                                const mm::DepthCompletionParams& params, int threads = 2) {
  mm::DepthCompleter completer(threads);
  return completer.complete(points, smallCamera(), {smallImage(), 1}, params);
}
}  // namespace

TEST(GroundGp, RecoversAFlatRoadAndItsVarianceGrowsAwayFromSamples) {
  // Samples on the ground plane 1.3 m below a level camera, only in the lower-left quadrant.
  std::vector<Eigen::Vector3d> points;
  for (int v = 70; v < 120; v += 5) {
    for (int u = 0; u < 80; u += 5) {
      const double z = 1.3 / ((v - 60) / 100.0);
      points.push_back(pointOnPixelRay(smallCamera(), u, v, z));
    }
  }
  const auto map = completeSmallImage(points, groundGpParams());
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
  for (float v : map.variance)
    ASSERT_TRUE(std::isfinite(v));
}

TEST(GroundGp, NearReturnsWinOverFarOnes) {
  // An object at 6 m seen by a few returns, with multipath returns at 40 m around it.
  std::vector<Eigen::Vector3d> points;
  for (int u = 60; u <= 100; u += 10) {
    points.push_back(pointOnPixelRay(smallCamera(), u, 50, 6.0));
    points.push_back(pointOnPixelRay(smallCamera(), u + 3, 52, 40.0));
  }
  const auto map = completeSmallImage(points, groundGpParams(), 1);
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
  for (double bad : {-1.0, std::nan("")}) {
    params.ground = {};
    params.ground.dense_vote_colour_sigma = bad;
    EXPECT_THROW(completer.complete({}, smallCamera(), {smallImage(), 1}, params), mm::InputError);
    params.ground = {};
    params.ground.dense_vote_colour_px = bad;
    EXPECT_THROW(completer.complete({}, smallCamera(), {smallImage(), 1}, params), mm::InputError);
  }
}

// --- dense-input mode ----------------------------------------------------------------------------

namespace {
// A sample every `step` pixels over rows [v0, v1) of the small camera, depth from `depth(u, v)`.
template <typename Depth>
std::vector<Eigen::Vector3d> denseScan(int v0, int v1, int step, Depth depth) {
  std::vector<Eigen::Vector3d> points;
  for (int v = v0; v < v1; v += step) {
    for (int u = 0; u < 160; u += step)
      points.push_back(pointOnPixelRay(smallCamera(), u, v, depth(u, v)));
  }
  return points;
}
}  // namespace

TEST(GroundGpDense, AutoModeFollowsTheSampleSpacing) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  const auto flat = [](int, int) { return 10.0; };
  // Small camera: ~0.57 deg per pixel. Every 2nd pixel is ~1.1 deg apart (dense for r = 2.5 deg
  // by the spacing <= r / 2 rule), every 8th ~4.6 deg (sparse).
  params.radius_deg = 2.5;
  EXPECT_TRUE(
      mm::groundInputIsDense(mm::toAngularSamples(denseScan(0, 120, 2, flat)), angles, params));
  EXPECT_FALSE(
      mm::groundInputIsDense(mm::toAngularSamples(denseScan(0, 120, 8, flat)), angles, params));
  params.ground.input = mm::GroundPriorParams::Input::kDense;
  EXPECT_TRUE(mm::groundInputIsDense({}, angles, params));
  params.ground.input = mm::GroundPriorParams::Input::kSparse;
  EXPECT_FALSE(
      mm::groundInputIsDense(mm::toAngularSamples(denseScan(0, 120, 2, flat)), angles, params));
  EXPECT_EQ(mm::parseGroundInput("dense"), mm::GroundPriorParams::Input::kDense);
  EXPECT_THROW(mm::parseGroundInput("lidar"), mm::InputError);
}

TEST(GroundGpDense, InverseDepthInterpolationIsExactOnTheRoad) {
  // Road 1.3 m below a level camera, a sample every 6 pixels: z = h / y is convex in the image,
  // so interpolating z (the linear baseline) overestimates between rows; 1/z is an affine function
  // of the image position on any plane, so interpolating it is nearly exact.
  const auto road = [](int, int v) { return 1.3 / ((v - 60) / 100.0); };
  const auto points = denseScan(66, 120, 6, road);
  mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  const auto map = completeSmallImage(points, params);
  params.model = mm::DepthModel::kLinear;
  const auto linear = completeSmallImage(points, params);
  double worst = 0.0, worst_linear = 0.0;
  for (int v = 69; v < 114; ++v) {
    for (int u = 10; u < 150; u += 7) {
      const std::size_t p = std::size_t(v) * 160 + u;
      worst = std::max(worst, std::abs(map.depth[p] - road(u, v)) / road(u, v));
      worst_linear = std::max(worst_linear, std::abs(linear.depth[p] - road(u, v)) / road(u, v));
    }
  }
  // Not exact: the barycentric weights are angular, which differs from the normalised image
  // position at second order in a triangle's size (here 6 px of a 77-degree-wide camera).
  EXPECT_LT(worst, 0.01) << worst_linear;
  EXPECT_GT(worst_linear, 4 * worst) << worst;
}

TEST(GroundGpDense, OcclusionEdgesAreNotBlended) {
  // A box at 5 m (columns 60-99, rows 30-69) in front of a wall at 20 m, sampled every 3 pixels.
  const auto scene = [](int u, int v) {
    return u >= 60 && u < 100 && v >= 30 && v < 70 ? 5.0 : 20.0;
  };
  const auto points = denseScan(0, 120, 3, scene);
  mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  params.ground.camera_height = 100.0;  // no ground in view: only the edge logic is tested
  const auto map = completeSmallImage(points, params);
  int blended = 0;
  for (int v = 3; v < 117; ++v) {
    for (int u = 3; u < 157; ++u) {
      const float z = map.depth[std::size_t(v) * 160 + u];
      blended += std::abs(z - 5.0f) > 0.05f && std::abs(z - 20.0f) > 0.2f;
    }
  }
  EXPECT_EQ(blended, 0);
  // Far from the edge: the right surface, with a small variance; on the edge a large one.
  EXPECT_NEAR(map.depth[std::size_t(50) * 160 + 80], 5.0f, 1e-3);
  EXPECT_NEAR(map.depth[std::size_t(100) * 160 + 20], 20.0f, 1e-2);
  EXPECT_LT(map.variance[std::size_t(50) * 160 + 80], 0.1f);
  EXPECT_GT(map.variance[std::size_t(50) * 160 + 100], 1.0f);
}

TEST(GroundGpDense, AFacadeSeenFromFarAlongTheStreetIsOneSurface) {
  // A wall 2 m to the right of the camera, parallel to its axis (z = 200 / (u - 80)), scanned every
  // 6 pixels: along a scan line neighbouring returns lie up to 27 % apart in depth (u = 102 and
  // 108: 9.1 and 7.1 m), far more than dense_edge_ratio, yet they and their neighbours lie on one
  // plane, so the triangles between them interpolate 1/z instead of taking one vertex's depth (a
  // wedge of error up to half the step).
  const auto wall = [](double u) { return 200.0 / (u - 80.0); };
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < 120; v += 6) {
    for (int u = 84; u < 160; u += 6)
      points.push_back(pointOnPixelRay(smallCamera(), u, v, wall(u)));
  }
  mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  params.ground.camera_height = 100.0;  // no ground in view: only the surfaces' logic is tested
  const auto map = completeSmallImage(points, params);
  double worst = 0.0;
  for (int v = 12; v < 102; v += 5) {
    for (int u = 97; u < 150; ++u)
      worst = std::max(worst, std::abs(map.depth[std::size_t(v) * 160 + u] - wall(u)) / wall(u));
  }
  // As on the road: exact up to the angular barycentric weights.
  EXPECT_LT(worst, 0.01);
}

TEST(GroundGpDense, TheEdgeRatioGrowsWithTheRingSpacing) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  const auto flat = [](int, int) { return 10.0; };
  mm::GroundPriorParams ground;  // 0.1, and 0.15 per degree of spacing
  // Small camera: ~0.57 deg per pixel. A return at every pixel: ~0.57 deg apart, below the
  // 0.67 deg at which 0.15 per degree reaches 0.1, so the fixed ratio stands.
  const auto every_pixel = mm::toAngularSamples(denseScan(0, 120, 1, flat));
  EXPECT_EQ(mm::denseEdgeRatio(every_pixel, angles, ground), 0.1);
  // Every 4th pixel: ~2 deg apart (the wide lens has fewer degrees per pixel off axis), a ratio
  // of ~0.3.
  const auto sparse = mm::toAngularSamples(denseScan(0, 120, 4, flat));
  const double spacing = mm::meanSampleSpacingDeg(sparse, angles);
  EXPECT_NEAR(spacing, 2.0, 0.1);
  EXPECT_DOUBLE_EQ(mm::denseEdgeRatio(sparse, angles, ground), 0.15 * spacing);
  // Off, or nothing in view: the fixed ratio.
  ground.dense_edge_ratio_per_deg = 0.0;
  EXPECT_EQ(mm::denseEdgeRatio(sparse, angles, ground), 0.1);
  ground.dense_edge_ratio_per_deg = 0.15;
  EXPECT_EQ(mm::denseEdgeRatio({}, angles, ground), 0.1);
  // The completion reports the ratio its dense mode used (and -1 in the sparse mode).
  mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  EXPECT_DOUBLE_EQ(completeSmallImage(denseScan(0, 120, 4, flat), params).stats.ground_edge_ratio,
                   0.15 * spacing);
  params.ground.input = mm::GroundPriorParams::Input::kSparse;
  EXPECT_EQ(completeSmallImage(denseScan(0, 120, 4, flat), params).stats.ground_edge_ratio, -1.0);
  params.ground.dense_edge_ratio_per_deg = -0.1;
  EXPECT_THROW(params.validate(), mm::InputError);
}

TEST(GroundGpDense, SparseRingsOnACurvedSurfaceAreOneSurface) {
  // A surface curving away (1/z not affine in the image, so the one-plane test does not merge its
  // triangles) scanned on lines 8 rows (~4 deg) apart, a return every 2 pixels along them:
  // neighbouring lines lie ~22 % apart in depth, beyond the fixed 10 %, within the ~0.3 that the
  // spacing (~2 deg) gives. As one surface the pixels between the lines interpolate; as an
  // occlusion edge each took one line's depth.
  const auto surface = [](int, int v) { return 10.0 * std::exp(0.025 * (v - 60)); };
  std::vector<Eigen::Vector3d> points;
  for (int v = 4; v < 120; v += 8) {
    for (int u = 0; u < 160; u += 2)
      points.push_back(pointOnPixelRay(smallCamera(), u, v, surface(u, v)));
  }
  mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  params.ground.camera_height = 100.0;  // no ground in view: only the surfaces' logic is tested
  const auto worstBetweenLines = [&](const mm::DepthMap& map) {
    double worst = 0.0;
    for (int v = 14; v < 106; ++v) {
      for (int u = 20; u < 140; u += 3) {
        const double truth = surface(u, v);
        worst = std::max(worst, std::abs(map.depth[std::size_t(v) * 160 + u] - truth) / truth);
      }
    }
    return worst;
  };
  const double scaled = worstBetweenLines(completeSmallImage(points, params));
  params.ground.dense_edge_ratio_per_deg = 0.0;
  const double fixed = worstBetweenLines(completeSmallImage(points, params));
  // Measured: 0.7 % against 10.5 % (half the step between the lines).
  EXPECT_LT(scaled, 0.015) << fixed;
  EXPECT_GT(fixed, 5 * scaled) << scaled;
}

TEST(GroundGpDense, TheRoadBetweenScanLinesFollowsThePlaneToTheObjectItMeets) {
  // Scan lines 12 rows (~7 deg) apart over a road 1.3 m below a level camera that ends at a wall
  // 12 m ahead (its foot at row ~71). The line at row 78 is on the road (7.2 m), the one at row 66
  // on the wall: their triangles span an occlusion edge. Between them the road goes on to the
  // wall's foot: holding the lower line's 7.2 m there would be up to 30 % short.
  const double wall = 12.0;
  const auto road = [](int v) { return 1.3 / ((v - 60) / 100.0); };
  const auto scene = [&](int, int v) { return v > 60 ? std::min(wall, road(v)) : wall; };
  std::vector<Eigen::Vector3d> points;
  for (int v = 6; v < 120; v += 12) {
    for (int u = 0; u < 160; u += 2)
      points.push_back(pointOnPixelRay(smallCamera(), u, v, scene(u, v)));
  }
  const mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  const auto map = completeSmallImage(points, params);
  for (int u = 20; u < 140; u += 11) {
    // Nearer the road's line than the wall's: the vote puts these pixels on the road.
    for (int v = 73; v < 78; ++v) {
      EXPECT_NEAR(map.depth[std::size_t(v) * 160 + u], road(v), 0.02 * road(v)) << u << "," << v;
    }
    // Never past the wall that ends the road.
    for (int v = 66; v <= 78; ++v) {
      EXPECT_LE(map.depth[std::size_t(v) * 160 + u], wall * 1.001) << u << "," << v;
    }
  }
}

TEST(GroundGpDense, EdgeVotesDependOnlyOnTheFrame) {
  // The occlusion-edge vote of a pixel may be reused for the next pixels of its triangle row; the
  // reuse must not reach into another frame (a triangle at the same address in the next call) or
  // depend on the thread count.
  const auto box = [](int left) {
    return [left](int u, int v) {
      return u >= left && u < left + 40 && v >= 30 && v < 70 ? 5.0 : 20.0;
    };
  };
  mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  params.ground.camera_height = 100.0;
  const auto first = denseScan(0, 120, 3, box(60));
  const auto second = denseScan(0, 120, 3, box(64));
  const mm::DepthMap fresh = completeSmallImage(second, params, 1);
  for (int threads : {1, 2, 3}) {
    mm::DepthCompleter completer(threads);
    completer.complete(first, smallCamera(), {smallImage(), 1}, params);
    const mm::DepthMap after = completer.complete(second, smallCamera(), {smallImage(), 1}, params);
    EXPECT_EQ(after.depth, fresh.depth) << threads << " threads";
    EXPECT_EQ(after.variance, fresh.variance) << threads << " threads";
  }
}

namespace {
// A box at 5 m (columns [40, 120), rows above 52) in front of a wall at 20 m, seen by scan lines
// 16 rows (~9 deg) apart, a return every 2 pixels: the box's lower edge lies between the lines at
// rows 40 and 56. The image shows it: the box red, the wall grey.
double boxOverWall(int u, int v) {
  return u >= 40 && u < 120 && v < 52 ? 5.0 : 20.0;
}

cv::Mat boxOverWallImage() {
  cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar(128, 128, 128));
  image(cv::Rect(40, 0, 80, 52)).setTo(cv::Scalar(0, 0, 200));
  return image;
}

std::vector<Eigen::Vector3d> sparseScanLines() {
  std::vector<Eigen::Vector3d> points;
  for (int v = 8; v < 120; v += 16) {
    for (int u = 0; u < 160; u += 2)
      points.push_back(pointOnPixelRay(smallCamera(), u, v, boxOverWall(u, v)));
  }
  return points;
}

// Pixels of rows [v0, v1) in the box's columns (away from its sides) whose depth is off the
// scene's by more than 1 m.
int wrongSurfacePixels(const mm::DepthMap& map, int v0, int v1) {
  int wrong = 0;
  for (int v = v0; v < v1; ++v) {
    for (int u = 50; u < 110; ++u)
      wrong += std::abs(map.depth[std::size_t(v) * 160 + u] - boxOverWall(u, v)) > 1.0;
  }
  return wrong;
}
}  // namespace

TEST(GroundGpDense, ColoursPutPixelsBetweenScanLinesOnTheSurfaceTheyLookLike) {
  mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  params.ground.camera_height = 100.0;       // no ground in view: only the edge vote is tested
  params.ground.dense_vote_colour_px = 4.0;  // the small camera's pixels are ~0.6 deg
  mm::DepthCompleter completer(2);
  const auto points = sparseScanLines();
  const mm::DepthMap by_angle =
      completer.complete(points, smallCamera(), {smallImage(), 1}, params);
  const mm::DepthMap by_colour =
      completer.complete(points, smallCamera(), {smallImage(), 1}, params, boxOverWallImage());
  // By angle alone the pixels nearer the line at row 56 than the one at row 40 take the wall
  // (180 of them); with the colours those whose nearest returns include the box's take the box
  // (109 left: the colours reweigh a pixel's nearest returns, and where all of them lie on the
  // wall they cannot bring the box back).
  const int box_wrong_by_angle = wrongSurfacePixels(by_angle, 41, 52);
  const int box_wrong_by_colour = wrongSurfacePixels(by_colour, 41, 52);
  EXPECT_GT(box_wrong_by_angle, 100);
  EXPECT_LT(box_wrong_by_colour, 0.7 * box_wrong_by_angle) << box_wrong_by_angle;
  // The wall below the edge stays the wall.
  EXPECT_EQ(wrongSurfacePixels(by_angle, 52, 56), 0);
  EXPECT_EQ(wrongSurfacePixels(by_colour, 52, 56), 0);
  // Each thread keeps its own colour caches: the same depth on any number of threads, and in a
  // second call (a fresh image).
  for (int threads : {1, 3}) {
    mm::DepthCompleter other(threads);
    other.complete(points, smallCamera(), {smallImage(), 1}, params,
                   cv::Mat(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(7)));
    const mm::DepthMap again =
        other.complete(points, smallCamera(), {smallImage(), 1}, params, boxOverWallImage());
    EXPECT_EQ(again.depth, by_colour.depth) << threads << " threads";
  }
}

TEST(GroundGpDense, ColoursChangeNothingWhereTheyCannotTellSurfacesApart) {
  mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  params.ground.camera_height = 100.0;
  params.ground.dense_vote_colour_px = 4.0;
  mm::DepthCompleter completer(2);
  const auto points = sparseScanLines();
  const mm::DepthMap without = completer.complete(points, smallCamera(), {smallImage(), 1}, params);
  // One colour everywhere: every return looks like every pixel.
  const cv::Mat grey(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(90));
  const mm::DepthMap uniform =
      completer.complete(points, smallCamera(), {smallImage(), 1}, params, grey);
  EXPECT_EQ(uniform.depth, without.depth);
  // Colours off: the image is not used.
  params.ground.dense_vote_colour_sigma = 0.0;
  const mm::DepthMap off =
      completer.complete(points, smallCamera(), {smallImage(), 1}, params, boxOverWallImage());
  EXPECT_EQ(off.depth, without.depth);
  EXPECT_EQ(off.variance, without.variance);
}

TEST(GroundGpDense, ColumnsExtendTheirTopmostReturnUpward) {
  // A wall 8 m ahead seen by rings from row 40 down (the LiDAR's highest ring at row 40), over a
  // road 1.3 m below a level camera. A vertical surface keeps its camera depth along an image
  // column, so above the top ring every column carries the wall's depth, more uncertain higher up.
  const double wall = 8.0;
  const auto scene = [wall](int, int v) {
    return v > 60 ? std::min(wall, 1.3 / ((v - 60) / 100.0)) : wall;
  };
  const auto points = denseScan(40, 120, 4, scene);
  const mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  const auto map = completeSmallImage(points, params);
  for (int u = 2; u < 158; u += 13) {
    for (int v = 0; v < 38; v += 5) {
      EXPECT_NEAR(map.depth[std::size_t(v) * 160 + u], wall, 1e-3) << u << "," << v;
    }
    // sigma / depth: the surface's own at the ring, plus relative_sigma_per_deg per degree above.
    const auto relative_sigma = [&](int v) {
      return std::sqrt(map.variance[std::size_t(v) * 160 + u]) / wall;
    };
    const double deg_per_px = 180.0 / (M_PI * 100.0);
    EXPECT_NEAR(
        relative_sigma(30),
        params.ground.dense_relative_sigma + params.ground.relative_sigma_per_deg * 10 * deg_per_px,
        1e-4);
    EXPECT_GT(relative_sigma(0), relative_sigma(30));
  }
}

TEST(GroundGpDense, TrianglesBridgingAnEmptyRegionDoNotOverrideTheExtension) {
  // The wall of the test above plus one high return far off to the right (a roof 7 % farther: the
  // same surface for the edge test): the hull-edge triangles from the top ring up to it span the
  // empty region above the ring, and interpolating across them would blend wall and roof.
  const double wall = 8.0;
  auto points = denseScan(40, 120, 2, [wall](int, int) { return wall; });
  points.push_back(pointOnPixelRay(smallCamera(), 150, 2, 8.6));
  const mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  const auto map = completeSmallImage(points, params);
  // Triangles with an edge over 20 mean spacings (here ~2 px, so ~23 deg) bridge; nearer the roof
  // return the triangles are shorter and their interpolation stands.
  for (const auto& [v, u] : {std::pair{20, 116}, {20, 124}, {30, 92}, {30, 100}, {30, 116}}) {
    EXPECT_NEAR(map.depth[std::size_t(v) * 160 + u], wall, 1e-3) << v << "," << u;
  }
  EXPECT_GT(map.depth[std::size_t(20) * 160 + 140], wall + 0.1);
}

TEST(GroundGpDense, ColumnsWhoseTopReturnIsGroundAreNotExtended) {
  // Only road returns: nothing vertical to extend; the pixels above keep the nearest-sample prior,
  // whose uncertainty starts at relative_sigma.
  const auto road = [](int, int v) { return 1.3 / ((v - 60) / 100.0); };
  const auto points = denseScan(70, 120, 4, road);
  const mm::DepthCompletionParams params = groundGpParams(mm::GroundPriorParams::Input::kDense);
  const auto map = completeSmallImage(points, params);
  const std::size_t above = std::size_t(50) * 160 + 80;
  EXPECT_GE(std::sqrt(map.variance[above]) / map.depth[above], params.ground.relative_sigma);
}

TEST(GroundPrior, SupportDistanceComesFromTheSupportSet) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  const auto objects = mm::toAngularSamples({pointOnPixelRay(smallCamera(), 20, 20, 5.0)});
  const auto support = mm::toAngularSamples(
      {pointOnPixelRay(smallCamera(), 20, 20, 5.0), pointOnPixelRay(smallCamera(), 120, 100, 9.0)});
  const auto own = mm::nearestSurfaceDepth(objects, angles, 1, 1, 1, pool);
  const auto with = mm::nearestSurfaceDepth(objects, angles, 1, 1, 1, pool, &support);
  const std::size_t at_second = std::size_t(100) * 160 + 120;
  EXPECT_EQ(own.depth[at_second], with.depth[at_second]);  // the surface: objects only
  EXPECT_GT(own.distance_deg[at_second], 20.0f);
  EXPECT_LT(with.distance_deg[at_second], 1e-3f);
}

TEST(GroundPrior, SurfaceRowsInterpolateLikeTheFullResolutionPrior) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  const auto samples = mm::toAngularSamples({pointOnPixelRay(smallCamera(), 20, 20, 5.0),
                                             pointOnPixelRay(smallCamera(), 120, 100, 9.0),
                                             pointOnPixelRay(smallCamera(), 70, 50, 14.0)});
  // A lattice step that does not divide the grid: the last row and column are extra nodes.
  const auto full = mm::nearestSurfaceDepth(samples, angles, 2, 1, 7, pool);
  const auto rows = mm::nearestSurfaceRows(samples, angles, 2, 1, 7, pool);
  ASSERT_TRUE(rows.has_depth);
  for (int r = 0; r < angles.grid().rows(); ++r) {
    const auto w = rows.row(r);
    for (int c = 0; c < angles.grid().cols(); ++c) {
      const std::size_t p = std::size_t(r) * angles.grid().cols() + c;
      ASSERT_EQ(rows.depth(r, c), full.depth[p]) << r << "," << c;
      ASSERT_EQ(mm::NearestSurfaceRows::lerp(w.distance_lo[c], w.distance_hi[c], w.t),
                full.distance_deg[p]);
    }
  }
  // Without samples: no surface anywhere.
  const auto none = mm::nearestSurfaceRows({}, angles, 2, 1, 7, pool);
  EXPECT_FALSE(none.has_depth);
  EXPECT_TRUE(std::isinf(none.depth(5, 5)));
}

TEST(GroundPrior, SingleColumnGridIsCoveredByTheLattice) {
  // A one-pixel-wide grid has a single lattice column: every pixel still gets the surface.
  const mm::PixelAngleGrid angles(smallCamera(), {{120, 1}, 1});
  mm::ThreadPool pool(2);
  const auto samples = mm::toAngularSamples({pointOnPixelRay(smallCamera(), 0, 60, 6.0)});
  const auto full = mm::nearestSurfaceDepth(samples, angles, 1, 1, 16, pool);
  for (float d : full.depth)
    EXPECT_FLOAT_EQ(d, 6.0f);
}

TEST(GroundPrior, NearestSurfaceTiesGoToTheEarlierSample) {
  // Three returns in one direction are equally near every pixel: the k nearest are the earliest.
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  std::vector<mm::AngularSample> samples = {{-20.0f, 5.0f, 50.0f},
                                            {3.0f, -2.0f, 30.0f},
                                            {3.0f, -2.0f, 10.0f},
                                            {3.0f, -2.0f, 20.0f},
                                            {25.0f, 1.0f, 40.0f}};
  const auto lattice = mm::nearestSurfaceRows(samples, angles, 2, 2, 4, pool);
  const float at_node = lattice.depth(60, 80);  // nearest to all three: (30, 10), not (10, 20)
  EXPECT_EQ(at_node, 30.0f);
}

TEST(GroundPrior, NearestSurfaceMatchesAFullSortAtEveryNode) {
  // The k nearest by (squared float distance, index), as a full sort finds them; quantised angles
  // make ties, duplicates and a support set exercise every path of the search.
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::ThreadPool pool(2);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> az(-80, 80), el(-60, 60), depth(1, 60);
  auto draw = [&](int n) {
    std::vector<mm::AngularSample> v;
    for (int i = 0; i < n; ++i) {
      v.push_back({az(rng) * 0.5f, el(rng) * 0.5f, static_cast<float>(depth(rng))});
      if (i % 7 == 3) v.push_back(v[rng() % v.size()]);
    }
    return v;
  };
  const std::vector<mm::AngularSample> samples = draw(150), support = draw(300);
  const int step = 6;
  for (const auto& [k, rank] : {std::pair{1, 1}, {2, 2}, {8, 2}, {8, 5}, {40, 3}}) {
    const auto lattice = mm::nearestSurfaceRows(samples, angles, k, rank, step, pool, &support);
    for (std::size_t i = 0; i < lattice.node_rows.size(); ++i) {
      const int r = lattice.node_rows[i];
      for (int c = 0; c < lattice.cols; c += step) {
        const float qaz = angles.azimuthRow(r)[c], qel = angles.elevationRow(r)[c];
        auto squared = [&](const mm::AngularSample& s) {
          const float da = s.azimuth_deg - qaz, de = s.elevation_deg - qel;
          return da * da + de * de;
        };
        std::vector<std::pair<float, int>> order;
        for (std::size_t j = 0; j < samples.size(); ++j)
          order.emplace_back(squared(samples[j]), static_cast<int>(j));
        std::sort(order.begin(), order.end());
        std::vector<float> depths;
        for (int t = 0; t < k; ++t)
          depths.push_back(samples[order[t].second].depth);
        std::sort(depths.begin(), depths.end());
        float nearest_support = INFINITY;
        for (const auto& s : support)
          nearest_support = std::min(nearest_support, squared(s));
        const std::size_t p = i * lattice.cols + c;
        ASSERT_EQ(lattice.depth_rows[p], depths[rank - 1]) << k << " " << r << "," << c;
        ASSERT_EQ(lattice.distance_rows[p], static_cast<float>(std::sqrt(double(nearest_support))));
      }
    }
  }
}

// --- calibration ---------------------------------------------------------------------------------

TEST(Calibration, CentralNormalQuantiles) {
  EXPECT_NEAR(mm::centralNormalQuantile(0.95), 1.959963985, 1e-8);
  EXPECT_NEAR(mm::centralNormalQuantile(0.6826894921), 1.0, 1e-8);
  EXPECT_NEAR(mm::centralNormalQuantile(0.5), 0.6744897502, 1e-8);
  EXPECT_THROW(mm::centralNormalQuantile(1.0), mm::InputError);
}

TEST(Calibration, CountsTruthInsideTheIntervals) {
  // Errors of 0.5, 1.5, 2.5 sigma (sigma = 2), one pixel without truth, one not predicted.
  const std::vector<float> prediction = {10.0f, 10.0f, 10.0f, 10.0f, -1.0f};
  const std::vector<float> variance = {4.0f, 4.0f, 4.0f, 4.0f, 4.0f};
  const std::vector<float> truth = {11.0f, 7.0f, 15.0f, 0.0f, 10.0f};
  const std::vector<double> levels = {0.5, 0.9, 0.99};  // z = 0.674, 1.645, 2.576
  const auto counts = mm::evaluateCalibration(prediction.data(), variance.data(), nullptr,
                                              truth.data(), truth.size(), {}, levels);
  EXPECT_EQ(counts.count, 3);
  EXPECT_EQ(counts.inside, (std::vector<long long>{1, 2, 3}));
  EXPECT_NEAR(counts.observed(1), 2.0 / 3.0, 1e-12);
  mm::CalibrationCounts total = counts;
  total.merge(counts);
  EXPECT_EQ(total.count, 6);
  EXPECT_EQ(total.inside[2], 6);
  mm::CalibrationCounts other = counts;
  other.levels = {0.5};
  EXPECT_THROW(total.merge(other), mm::InputError);
}

// --- large neighbour sets: the tiled residual GP
// ---------------------------------------------------

namespace {
// A scene for the residual GP: a wall at 12 m over the upper rows and a car at 7 m in the middle,
// one return every `step` pixels, some of them multipath returns 20 m behind.
std::vector<Eigen::Vector3d> wallAndCar(int step) {
  std::vector<Eigen::Vector3d> points;
  for (int v = 5; v < 60; v += step) {
    for (int u = 2; u < 160; u += step) {
      const bool car = u > 50 && u < 110 && v > 35;
      const bool multipath = (u + v) % 7 == 0;
      points.push_back(pointOnPixelRay(smallCamera(), u, v, (car ? 7.0 : 12.0) + multipath * 20));
    }
  }
  return points;
}
}  // namespace

TEST(GroundGpTiled, SwitchesOnlyWhenNeighbourSetsAreLarge) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  auto params = groundGpParams(mm::GroundPriorParams::Input::kSparse);
  // ~0.57 deg per pixel: within 3 deg a return every 2 px has ~20 others, every 6 px a few.
  params.radius_deg = 3.0;
  const auto dense = mm::toAngularSamples(wallAndCar(2));
  const auto sparse = mm::toAngularSamples(wallAndCar(6));
  EXPECT_GT(mm::meanSamplesWithinRadius(dense, angles, params), 18.0);
  EXPECT_LT(mm::meanSamplesWithinRadius(sparse, angles, params), 6.0);
  EXPECT_TRUE(mm::groundGpUsesTiles(dense, angles, params));
  EXPECT_FALSE(mm::groundGpUsesTiles(sparse, angles, params));
  // One lone return counts itself; returns out of view do not count.
  EXPECT_EQ(mm::meanSamplesWithinRadius(mm::toAngularSamples({{0.0, 0.0, 10.0}}), angles, params),
            1.0);
  EXPECT_EQ(mm::meanSamplesWithinRadius(mm::toAngularSamples({{0.0, 0.0, -10.0}}), angles, params),
            0.0);
  params.max_neighbors = 8;  // asked for explicitly
  EXPECT_TRUE(mm::groundGpUsesTiles(sparse, angles, params));

  EXPECT_EQ(completeSmallImage(wallAndCar(2), params).stats.ground_mode, "sparse_tiled");
  EXPECT_EQ(completeSmallImage(wallAndCar(6), groundGpParams(mm::GroundPriorParams::Input::kSparse))
                .stats.ground_mode,
            "sparse");
  // image_guided on ground_gp's prediction runs the same ground_gp and reports its mode.
  mm::DepthCompletionParams guided = params;
  guided.model = mm::DepthModel::kImageGuided;
  guided.guided.ground_gp_prior = true;
  const cv::Mat image(smallImage().height, smallImage().width, CV_8UC3, cv::Scalar::all(90));
  mm::DepthCompleter completer(2);
  EXPECT_EQ(completer.complete(wallAndCar(2), smallCamera(), {smallImage(), 1}, guided, image)
                .stats.ground_mode,
            "sparse_tiled");
}

TEST(GroundGpTiled, ResidualGpIsCloseToTheExactOneAndIndependentOfThreads) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  auto params = groundGpParams(mm::GroundPriorParams::Input::kSparse);
  params.max_neighbors = 16;
  params.approx_tile = 8;
  const auto samples = mm::toAngularSamples(wallAndCar(2));
  const mm::GroundPlane plane = mm::givenGroundPlane(params.ground);
  const double median = mm::computeShift(mm::DepthShift{}, samples);
  mm::ThreadPool pool(2);
  const auto sets = mm::NeighbourSets::build(samples, angles, 2.0f, pool);
  mm::PixelPredictions exact, tiled;
  mm::predictGroundGp(samples, angles, &sets, params, plane, median, pool, exact);
  mm::predictGroundGp(samples, angles, nullptr, params, plane, median, pool, tiled);
  // The residual GP has amplitude 1 m and residuals in [-3, 0] m: the approximation moves the
  // depth by less than 3 m anywhere, and by centimetres on average.
  double total = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < exact.mean.size(); ++i) {
    const double d = std::abs(double(tiled.mean[i]) - exact.mean[i]);
    total += d;
    worst = std::max(worst, d);
    ASSERT_TRUE(std::isfinite(tiled.variance[i]) && tiled.variance[i] > 0.0f) << i;
  }
  EXPECT_LT(total / exact.mean.size(), 0.05) << total / exact.mean.size();
  EXPECT_LT(worst, 3.0);
  for (int threads : {1, 3}) {
    mm::ThreadPool other(threads);
    mm::PixelPredictions again;
    mm::predictGroundGp(samples, angles, nullptr, params, plane, median, other, again);
    ASSERT_EQ(again.mean, tiled.mean) << threads;
    ASSERT_EQ(again.variance, tiled.variance) << threads;
  }
}

// ground_gp runs the tiled residual GP in single precision (search likelihood and per-pixel step):
// on residual-like targets (amplitude 1 m, values in [-3, 0] m) it agrees with the double one to
// float rounding almost everywhere; a length-scale search that stops elsewhere on a flat
// likelihood may move a tile by more, so the bound on the worst pixel is looser.
TEST(GroundGpTiled, SinglePrecisionAgreesWithDouble) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  auto params = groundGpParams(mm::GroundPriorParams::Input::kSparse);
  params.max_neighbors = 16;
  params.approx_tile = 8;
  params.gp.amplitude = params.ground.residual_amplitude;
  const auto samples = mm::toAngularSamples(wallAndCar(2));
  std::vector<double> targets(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i)
    targets[i] = -3.0 * static_cast<double>((i * 7919) % 101) / 100.0;
  mm::ThreadPool pool(2);
  mm::PixelPredictions in_double, in_single;
  const int tiles = mm::predictTiledLocalGp(samples, targets, angles, params, mm::PriorMean{0.0},
                                            pool, in_double, mm::PredictionPrecision::kDouble);
  ASSERT_GT(tiles, 0);
  EXPECT_EQ(mm::predictTiledLocalGp(samples, targets, angles, params, mm::PriorMean{0.0}, pool,
                                    in_single, mm::PredictionPrecision::kSingle),
            tiles);
  ASSERT_EQ(in_single.mean.size(), in_double.mean.size());
  std::size_t close = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < in_double.mean.size(); ++i) {
    ASSERT_TRUE(std::isfinite(in_single.mean[i]) && std::isfinite(in_single.variance[i])) << i;
    ASSERT_GE(in_single.variance[i], 0.0f) << i;
    const double d = std::abs(double(in_single.mean[i]) - in_double.mean[i]);
    close += d <= 1e-3;
    worst = std::max(worst, d);
  }
  EXPECT_GE(close, in_double.mean.size() * 99 / 100) << close << " of " << in_double.mean.size();
  EXPECT_LT(worst, 0.5);
}
