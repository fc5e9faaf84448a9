// The ground plane from the returns (RANSAC), the plane and mode ground_gp chooses, the pose as an
// optional source of the plane, and the variance calibration.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
#include "multimodal_nvs/core/depth/models/ground_gp_model.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/variance_calibration.hpp"
#include "multimodal_nvs/core/eval/depth_metrics.hpp"

namespace mm = multimodal_nvs;
using mm::test::pointOnPixelRay;
using mm::test::smallCamera;
using mm::test::smallImage;

namespace {
constexpr double kPi = 3.14159265358979323846;

// World up in the camera frame of a camera pitched up by `pitch_deg`.
Eigen::Vector3d upForPitch(double pitch_deg) {
  const double p = pitch_deg * kPi / 180.0;
  return {0.0, -std::cos(p), std::sin(p)};
}

// A scan of the road (height h under a camera pitched by pitch_deg) seen every `step` pixels below
// the horizon, plus a wall of returns 12 m ahead in the upper rows; `elevation_noise_deg` moves
// every return along its ray's elevation (radar's coarse elevation).
std::vector<Eigen::Vector3d> roadScan(double height, double pitch_deg, int step,
                                      double elevation_noise_deg, unsigned seed = 1) {
  const mm::PinholeIntrinsics k = smallCamera();
  const Eigen::Vector3d up = upForPitch(pitch_deg);
  std::mt19937 rng(seed);
  // A normal distribution needs a positive spread (libstdc++ asserts it); it is drawn from only
  // when there is noise.
  std::normal_distribution<double> noise(0.0, std::max(elevation_noise_deg, 1e-9) * kPi / 180.0);
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < 120; v += step) {
    for (int u = 0; u < 160; u += step) {
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const double descent = up.dot(ray);
      double z = v < 40 ? 12.0 : (descent < 0.0 ? -height / descent : 0.0);
      if (!(z > 0.0) || z > 35.0) continue;
      Eigen::Vector3d p = ray * z;
      if (elevation_noise_deg > 0.0) p.y() += std::tan(noise(rng)) * z;
      points.push_back(p);
    }
  }
  return points;
}
}  // namespace

TEST(GroundPlaneEstimate, RecoversHeightAndPitchOfTheRoadFromPreciseReturns) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::GroundPriorParams params;  // expected: level camera at 1.3 m
  const auto samples = mm::toAngularSamples(roadScan(1.7, 4.0, 3, 0.0));
  const mm::GroundPlaneFit fit =
      mm::estimateGroundPlane(samples, angles, mm::givenGroundPlane(params), params);
  ASSERT_TRUE(fit.found);
  EXPECT_NEAR(fit.plane.height, 1.7, 0.02);
  EXPECT_LT(std::acos(std::min(1.0, fit.plane.up.dot(upForPitch(4.0)))) * 180.0 / kPi, 0.5);
  EXPECT_GT(fit.inlier_fraction, 0.5);  // the wall rows are not on the plane
  EXPECT_LT(fit.inlier_fraction, 1.0);
  // Deterministic.
  const mm::GroundPlaneFit again =
      mm::estimateGroundPlane(samples, angles, mm::givenGroundPlane(params), params);
  EXPECT_EQ(again.plane.height, fit.plane.height);
  EXPECT_EQ(again.inliers, fit.inliers);
}

TEST(GroundPlaneEstimate, PreciseReturnsGiveThePlaneAndTheDenseMode) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  // Sparse by the half-radius spacing rule (every 3rd pixel, ~1.7 deg apart, r = 2 deg): the
  // precise fit decides, with returns within the radius of each other.
  const auto samples = mm::toAngularSamples(roadScan(1.7, 4.0, 3, 0.0));
  ASSERT_FALSE(mm::groundInputIsDense(samples, angles, params));
  const mm::GroundChoice choice = mm::chooseGround(samples, angles, params);
  EXPECT_TRUE(choice.dense);
  EXPECT_EQ(choice.source, mm::GroundPriorParams::PlaneSource::kReturns);
  EXPECT_NEAR(choice.plane.height, 1.7, 0.05);
  // Without estimation the given plane stays, the mode is still judged from the returns.
  params.ground.estimate_plane = false;
  const mm::GroundChoice given = mm::chooseGround(samples, angles, params);
  EXPECT_TRUE(given.dense);
  EXPECT_EQ(given.source, mm::GroundPriorParams::PlaneSource::kParameters);
  EXPECT_EQ(given.plane.height, 1.3);
  // A forced mode wins.
  params.ground.input = mm::GroundPriorParams::Input::kSparse;
  EXPECT_FALSE(mm::chooseGround(samples, angles, params).dense);
}

TEST(GroundPlaneEstimate, PreciseButSparseScatteredReturnsKeepTheSparseMode) {
  // A radar mounted high sees much road: returns every 8th pixel (~4.6 deg apart, not on scan
  // lines), exactly on the plane. The plane is taken from them, the mode stays sparse.
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  const std::vector<Eigen::Vector3d> points = roadScan(1.7, 4.0, 8, 0.0);
  const auto samples = mm::toAngularSamples(points);
  const mm::GroundChoice choice = mm::chooseGround(samples, angles, params);
  EXPECT_GE(choice.inlier_fraction, params.ground.precise_fraction);
  EXPECT_EQ(choice.source, mm::GroundPriorParams::PlaneSource::kReturns);
  EXPECT_NEAR(choice.plane.height, 1.7, 0.05);
  EXPECT_GT(mm::meanSampleSpacingDeg(samples, angles), params.radius_deg);
  EXPECT_LT(choice.scan_line_share, 0.4);
  EXPECT_FALSE(choice.dense);
}

TEST(GroundPlaneEstimate, AFewDozenReturnsOnOnePlaneKeepTheGivenPlane) {
  // The same road, every 3rd of those returns: still every one of them on the plane, but too few
  // for a verdict of precision (among a few dozen scattered radar returns a quarter lies on some
  // wrong plane by chance).
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  const std::vector<Eigen::Vector3d> all = roadScan(1.7, 4.0, 8, 0.0);
  std::vector<Eigen::Vector3d> few;
  for (std::size_t i = 0; i < all.size(); i += 3)
    few.push_back(all[i]);
  const auto samples = mm::toAngularSamples(few);
  const mm::GroundPlaneFit fit =
      mm::estimateGroundPlane(samples, angles, mm::givenGroundPlane(params.ground), params.ground);
  ASSERT_TRUE(fit.found);
  ASSERT_GE(fit.inliers, 30u);
  ASSERT_LT(fit.inliers, 80u);
  EXPECT_GE(fit.inlier_fraction, params.ground.precise_fraction);
  EXPECT_NEAR(fit.plane.height, 1.7, 0.05);
  const mm::GroundChoice choice = mm::chooseGround(samples, angles, params);
  EXPECT_EQ(choice.source, mm::GroundPriorParams::PlaneSource::kParameters);
  EXPECT_EQ(choice.plane.height, 1.3);
  EXPECT_FALSE(choice.dense);
  // All of them (the test above) are enough.
  ASSERT_GE(mm::estimateGroundPlane(mm::toAngularSamples(all), angles,
                                    mm::givenGroundPlane(params.ground), params.ground)
                .inliers,
            80u);
}

TEST(GroundPlaneEstimate, RadarLikeReturnsKeepTheGivenPlaneAndTheSparseMode) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  params.radius_deg = 5.0;
  // Dense by the old spacing rule (every 2nd pixel, r = 5 deg), but with 1.5 deg of elevation
  // noise.
  const auto samples = mm::toAngularSamples(roadScan(1.7, 4.0, 2, 1.5));
  ASSERT_TRUE(mm::groundInputIsDense(samples, angles, params));
  const mm::GroundChoice choice = mm::chooseGround(samples, angles, params);
  EXPECT_FALSE(choice.dense);
  EXPECT_LT(choice.inlier_fraction, params.ground.precise_fraction);
  EXPECT_EQ(choice.source, mm::GroundPriorParams::PlaneSource::kParameters);
  EXPECT_EQ(choice.plane.height, 1.3);
  EXPECT_FALSE(choice.single_scan_plane);  // returns off the road: elevation measured
}

namespace {
// A 2D scanner: every return on the horizontal plane 0.5 m below the camera, out to 30 m; all
// within 1.5 deg of elevation spread.
std::vector<Eigen::Vector3d> scanPlaneReturns() {
  std::vector<Eigen::Vector3d> scan;
  for (int i = 0; i < 200; ++i) {
    const double az = (-35.0 + 0.35 * i) * kPi / 180.0, range = 20.0 + 10.0 * std::sin(i);
    scan.push_back({range * std::sin(az), 0.5, range * std::cos(az)});
  }
  return scan;
}
}  // namespace

TEST(GroundPlaneEstimate, ReturnsOnOneScanPlaneOrTooFewGiveNoFit) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::GroundPriorParams params;
  std::vector<Eigen::Vector3d> scan = scanPlaneReturns();
  const auto plane = mm::givenGroundPlane(params);
  const auto flat = mm::estimateGroundPlane(mm::toAngularSamples(scan), angles, plane, params);
  EXPECT_FALSE(flat.found);
  EXPECT_TRUE(flat.single_scan_plane);  // its returns' pixel rows are not measured
  scan.resize(10);
  const auto few = mm::estimateGroundPlane(mm::toAngularSamples(scan), angles, plane, params);
  EXPECT_FALSE(few.found);
  EXPECT_EQ(few.inliers, 0u);
  EXPECT_FALSE(few.single_scan_plane);  // too few for a verdict
  // The verdict reaches the model's choice.
  mm::DepthCompletionParams radar;
  radar.model = mm::DepthModel::kGroundGp;
  EXPECT_TRUE(
      mm::chooseGround(mm::toAngularSamples(scanPlaneReturns()), angles, radar).single_scan_plane);
  // Without a verdict, the spacing rule decides (200 returns, ~0.35 deg apart along one line).
  mm::DepthCompletionParams p;
  p.model = mm::DepthModel::kGroundGp;
  EXPECT_EQ(mm::chooseGround({}, angles, p).dense, mm::groundInputIsDense({}, angles, p));
}

namespace {
// A scanning LiDAR seen by the small camera (level, 1.5 m above the road): rings every
// `ring_step_deg` of elevation from +20 to -28 deg, a return every 0.4 deg of azimuth on each.
// Above the horizon the rings hit a wall 15 m ahead; below it they hit the road, except where a
// vehicle (8 m ahead) stands in `blocked` of every 10 deg of azimuth.
std::vector<Eigen::Vector3d> ringScan(double ring_step_deg, double blocked) {
  std::vector<Eigen::Vector3d> points;
  for (double el = 20.0; el >= -28.0; el -= ring_step_deg) {
    for (double az = -38.0; az <= 38.0; az += 0.4) {
      const Eigen::Vector2d ray = mm::normalisedFromAngles(az, el);
      double z = 15.0;
      if (el < 0.0) {
        const double in_period = std::fmod(az + 40.0, 10.0) / 10.0;
        z = in_period < blocked ? 8.0 : 1.5 / ray.y();
      }
      points.push_back({ray.x() * z, ray.y() * z, z});
    }
  }
  return points;
}

// The nearest-neighbour share along rows, by brute force (what scanLineShare must equal when every
// return is a query).
double bruteForceScanLineShare(const std::vector<mm::AngularSample>& samples) {
  const double slope = std::tan(20.0 * kPi / 180.0);
  std::size_t along = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    double best = INFINITY, daz = 0, del = 0;
    for (std::size_t j = 0; j < samples.size(); ++j) {
      if (j == i) continue;
      const double a = samples[j].azimuth_deg - samples[i].azimuth_deg;
      const double e = samples[j].elevation_deg - samples[i].elevation_deg;
      if (a * a + e * e < best) {
        best = a * a + e * e;
        daz = a;
        del = e;
      }
    }
    along += std::abs(del) <= slope * std::abs(daz);
  }
  return double(along) / double(samples.size());
}
}  // namespace

TEST(GroundPlaneEstimate, LidarRingsWithFewRoadReturnsStillGiveTheDenseMode) {
  // Traffic hides most of the road: too few road returns for the precision test, but the returns
  // lie on scan lines, so the mode is dense (the inlier fraction alone chose the radar mode here).
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  for (double ring_step : {2.0, 1.0}) {  // 16- and 32-beam-like ring spacing
    const auto samples = mm::toAngularSamples(ringScan(ring_step, 0.6));
    const mm::GroundChoice choice = mm::chooseGround(samples, angles, params);
    ASSERT_GT(choice.inlier_fraction, 0.1) << ring_step;
    ASSERT_LT(choice.inlier_fraction, params.ground.precise_fraction) << ring_step;
    EXPECT_GT(choice.scan_line_share, 0.9) << ring_step;
    EXPECT_TRUE(choice.dense) << ring_step;
    EXPECT_EQ(choice.source, mm::GroundPriorParams::PlaneSource::kParameters) << ring_step;
  }
  // The same scene as scattered returns (radar-like: no scan lines) stays sparse.
  std::vector<Eigen::Vector3d> scattered;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> az(-38.0, 38.0), el(-28.0, 20.0), unit(0.0, 1.0);
  for (int i = 0; i < 600; ++i) {
    const double a = az(rng), e = el(rng);
    const Eigen::Vector2d ray = mm::normalisedFromAngles(a, e);
    const double z = e >= 0.0 ? 15.0 : (unit(rng) < 0.6 ? 8.0 : 1.5 / ray.y());
    scattered.push_back({ray.x() * z, ray.y() * z, z});
  }
  const mm::GroundChoice radar = mm::chooseGround(mm::toAngularSamples(scattered), angles, params);
  ASSERT_GT(radar.inlier_fraction, 0.1);
  ASSERT_LT(radar.inlier_fraction, params.ground.precise_fraction);
  EXPECT_LT(radar.scan_line_share, 0.35);
  EXPECT_FALSE(radar.dense);
}

TEST(GroundPlaneEstimate, ScanLineShareFindsTheExactNearestNeighbour) {
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 159.0), v(0.0, 119.0), noise(-0.3, 0.3);
  for (int trial = 0; trial < 4; ++trial) {
    std::vector<Eigen::Vector3d> points;
    // Clusters and a lattice with jitter: ties and empty grid cells both occur.
    for (int i = 0; i < 300; ++i) {
      const double pu = trial % 2 == 0 ? u(rng) : 1.0 + 10.0 * (i % 15) + noise(rng);
      const double pv =
          trial % 2 == 0 ? v(rng) * (i % 3 == 0 ? 0.2 : 1.0) : 1.0 + 6.0 * (i / 15) + noise(rng);
      points.push_back(pointOnPixelRay(smallCamera(), pu, pv, 5.0 + i % 7));
    }
    const auto samples = mm::toAngularSamples(points);
    EXPECT_NEAR(mm::scanLineShare(samples, angles), bruteForceScanLineShare(samples), 1e-12)
        << "trial " << trial;
  }
  EXPECT_EQ(mm::scanLineShare({}, angles), 0.0);
}

TEST(GroundPlaneEstimate, DepthStatsReportSourceAndMode) {
  mm::DepthCompleter completer(2);
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  const mm::DepthMap map =
      completer.complete(roadScan(1.7, 4.0, 3, 0.0), smallCamera(), {smallImage(), 1}, params);
  EXPECT_EQ(map.stats.ground_source, "returns");
  EXPECT_EQ(map.stats.ground_mode, "dense");
  EXPECT_GT(map.stats.ground_inlier_fraction, 0.5);
  // The plane that ran: the road's, 1.7 m below a camera looking 4 deg up.
  EXPECT_NEAR(map.stats.ground_camera_height, 1.7, 0.02);
  EXPECT_NEAR(map.stats.ground_pitch_deg, 4.0, 0.2);
  EXPECT_NEAR(map.stats.ground_roll_deg, 0.0, 0.2);
  params.model = mm::DepthModel::kNearest;
  EXPECT_EQ(completer.complete(roadScan(1.7, 4.0, 3, 0.0), smallCamera(), {smallImage(), 1}, params)
                .stats.ground_mode,
            "");
}

TEST(GroundPlaneEstimate, PoseSetsTheUpDirectionAndOnlyAPlausibleHeight) {
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();
  pose.block<3, 3>(0, 0) << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // level camera, z-up world
  pose(2, 3) = 1.6;
  mm::GroundPriorParams params;
  mm::applyCameraPose(pose, params);
  EXPECT_EQ(params.plane_source, mm::GroundPriorParams::PlaneSource::kPose);
  EXPECT_NEAR(params.camera_height, 1.6, 1e-12);
  EXPECT_NEAR(params.up_y, -1.0, 1e-12);
  // A map frame whose z = 0 is not the road (the camera at z = -42 m): the height stays.
  mm::GroundPriorParams map_frame;
  pose(2, 3) = -42.0;
  mm::applyCameraPose(pose, map_frame);
  EXPECT_EQ(map_frame.camera_height, 1.3);
  EXPECT_EQ(map_frame.plane_source, mm::GroundPriorParams::PlaneSource::kPose);
  mm::DepthCompletionParams p;
  p.model = mm::DepthModel::kGroundGp;
  p.ground = map_frame;
  EXPECT_NO_THROW(p.validate());
}

TEST(VarianceCalibration, ScaleMakesTheIntervalHoldTheTargetShare) {
  // Errors N(0, 2^2) against a raw variance of 1: the calibrated variance is ~4.
  std::mt19937 rng(3);
  std::normal_distribution<float> error(0.0f, 2.0f);
  const std::size_t n = 20000;
  std::vector<float> mean(n), variance(n, 1.0f), truth(n, 10.0f);
  for (std::size_t i = 0; i < n; ++i)
    mean[i] = 10.0f + error(rng);
  mm::VarianceScaleFit fit;
  fit.add(mean.data(), variance.data(), truth.data(), nullptr, n);
  const mm::VarianceCalibration c = fit.fit(0.95, 0.95);
  EXPECT_NEAR(c.scale, 4.0, 0.25);
  mm::ThreadPool pool(2);
  c.applyTo(variance, pool);
  std::vector<std::uint8_t> all(n, 1);
  const mm::CalibrationCounts counts = mm::evaluateCalibration(
      mean.data(), variance.data(), all.data(), truth.data(), n, {}, {0.95});
  EXPECT_NEAR(counts.observed(0), 0.95, 0.002);
  // Pixels without truth or prediction do not count; nothing to fit throws.
  mm::VarianceScaleFit empty;
  const float inf = INFINITY, zero = 0.0f, m = 1.0f;
  empty.add(&m, &inf, &m, nullptr, 1);
  empty.add(&m, &m, &zero, nullptr, 1);
  EXPECT_EQ(empty.count(), 0u);
  EXPECT_THROW(empty.fit(), mm::InputError);
  EXPECT_THROW(fit.fit(0.95, 1.0), mm::InputError);
}
