// Returns the camera cannot see: a scanner above the camera sees past the top of a near box to the
// wall behind it; projected into the camera, those wall returns land on the box.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/angular_triangulation.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/core/depth/hidden_returns.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace mm = multimodal_nvs;
using mm::test::smallCamera;
using mm::test::smallImage;

namespace {

constexpr double kWallZ = 20.0;
constexpr double kBoxZ = 5.0;

/// Near surfaces at z = kBoxZ in front of a wall at kWallZ (camera frame, y down): camera-frame
/// rectangles [x0, x1] x [y0, y1].
struct Occluders {
  struct Rect {
    double x0, x1, y0, y1;
  };
  std::vector<Rect> rects;

  bool contains(double x, double y) const {
    for (const Rect& r : rects) {
      if (x >= r.x0 && x <= r.x1 && y >= r.y0 && y <= r.y1) return true;
    }
    return false;
  }
  /// Whether the segment from `from` to `to` (beyond the occluders) passes through one.
  bool blocks(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const {
    const double t = (kBoxZ - from.z()) / (to.z() - from.z());
    const Eigen::Vector3d at = from + t * (to - from);
    return contains(at.x(), at.y());
  }
};

/// A scanner at `origin` (camera frame) with scan lines every `line_deg` of elevation and a
/// return every 0.25 deg along each line: the first hit, occluder or wall.
std::vector<Eigen::Vector3d> scan(const Occluders& scene, const Eigen::Vector3d& origin,
                                  double line_deg) {
  std::vector<Eigen::Vector3d> points;
  constexpr double kDeg = M_PI / 180.0;
  for (double el = -25.0; el <= 25.0; el += line_deg) {
    for (double az = -40.0; az <= 40.0; az += 0.25) {
      const Eigen::Vector3d dir(std::sin(az * kDeg) * std::cos(el * kDeg), -std::sin(el * kDeg),
                                std::cos(az * kDeg) * std::cos(el * kDeg));
      const Eigen::Vector3d at_box = origin + (kBoxZ - origin.z()) / dir.z() * dir;
      points.push_back(scene.contains(at_box.x(), at_box.y())
                           ? at_box
                           : Eigen::Vector3d(origin + (kWallZ - origin.z()) / dir.z() * dir));
    }
  }
  return points;
}

/// The wall returns the camera (at the origin) cannot see, by the scene's geometry.
int trulyHidden(const Occluders& scene, const std::vector<Eigen::Vector3d>& points) {
  int hidden = 0;
  for (const Eigen::Vector3d& p : points)
    hidden += p.z() > kBoxZ + 1.0 && scene.blocks(Eigen::Vector3d::Zero(), p);
  return hidden;
}

/// Whether a sample is one of the points the camera cannot see.
bool hiddenSample(const Occluders& scene, const mm::AngularSample& s) {
  constexpr double kDeg = M_PI / 180.0;
  const double z = s.depth, x = z * std::tan(s.azimuth_deg * kDeg);
  const double y = -std::tan(s.elevation_deg * kDeg) * z / std::cos(s.azimuth_deg * kDeg);
  return z > kBoxZ + 1.0 && scene.blocks(Eigen::Vector3d::Zero(), Eigen::Vector3d(x, y, z));
}

const Eigen::Vector3d kScannerAbove(0.0, -0.6, 0.0);  // 0.6 m above the camera

}  // namespace

TEST(HiddenReturns, WallReturnsSeenPastTheTopOfABoxAreDropped) {
  // A box 4 m wide whose top is 0.1 m above the camera, 5 m ahead.
  const Occluders box{{{-2.0, 2.0, -0.1, 1.5}}};
  const std::vector<Eigen::Vector3d> points = scan(box, kScannerAbove, 0.4);
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  const auto samples = mm::toAngularSamples(points);
  std::size_t reported = 0;
  const auto visible =
      mm::dropReturnsHiddenFromCamera(samples, angles, 1.1, kScannerAbove, &reported);
  const int hidden = trulyHidden(box, points);
  ASSERT_GT(hidden, 100);  // the scene does what it is meant to
  int dropped_visible = 0, kept_hidden = 0;
  for (const mm::AngularSample& s : visible)
    kept_hidden += hiddenSample(box, s);
  const int dropped = static_cast<int>(samples.size() - visible.size());
  EXPECT_EQ(reported, std::size_t(dropped));
  // Every dropped return is a hidden one (none the camera sees), and most hidden ones go: those
  // left lie above the box's highest scan line in the image, with no box return above them.
  dropped_visible = dropped - (hidden - kept_hidden);
  EXPECT_EQ(dropped_visible, 0);
  EXPECT_GT(hidden - kept_hidden, hidden / 2) << hidden << " hidden, " << kept_hidden << " kept";
}

TEST(HiddenReturns, NothingIsDroppedWhenTheScannerSitsAtTheCamera) {
  const Occluders box{{{-2.0, 2.0, -0.1, 1.5}}};
  const std::vector<Eigen::Vector3d> points = scan(box, Eigen::Vector3d::Zero(), 0.4);
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  const auto samples = mm::toAngularSamples(points);
  EXPECT_EQ(mm::dropReturnsHiddenFromCamera(samples, angles, 1.1, Eigen::Vector3d::Zero()).size(),
            samples.size());
}

TEST(HiddenReturns, ReturnsThroughTheGapsOfARailingAreKept) {
  // Horizontal bars 0.1 m high, 0.6 m apart: the wall between them is seen by both sensors.
  Occluders railing;
  for (double y = -0.1; y < 1.5; y += 0.6)
    railing.rects.push_back({-2.0, 2.0, y, y + 0.1});
  const std::vector<Eigen::Vector3d> points = scan(railing, kScannerAbove, 0.4);
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  const auto samples = mm::toAngularSamples(points);
  const auto visible = mm::dropReturnsHiddenFromCamera(samples, angles, 1.1, kScannerAbove);
  int kept_hidden = 0;
  for (const mm::AngularSample& s : visible)
    kept_hidden += hiddenSample(railing, s);
  const int dropped = static_cast<int>(samples.size() - visible.size());
  EXPECT_EQ(dropped - (trulyHidden(railing, points) - kept_hidden), 0);
}

TEST(HiddenReturns, TheTriangulationFiltersTheSameWayOnItsThreadOrNot) {
  const Occluders box{{{-2.0, 2.0, -0.1, 1.5}}};
  const auto samples = mm::toAngularSamples(scan(box, kScannerAbove, 0.4));
  const mm::PixelAngleGrid angles(smallCamera(), {smallImage(), 1});
  mm::BackgroundTriangulation early(samples, angles, true, true, 1.1, kScannerAbove);
  mm::BackgroundTriangulation late(samples, angles, false, true, 1.1, kScannerAbove);
  const auto expected = mm::dropReturnsHiddenFromCamera(samples, angles, 1.1, kScannerAbove);
  ASSERT_LT(expected.size(), samples.size());
  for (mm::BackgroundTriangulation* t : {&early, &late}) {
    const std::vector<mm::AngularSample>& got = t->samples();
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].azimuth_deg, expected[i].azimuth_deg);
      EXPECT_EQ(got[i].depth, expected[i].depth);
    }
  }
  EXPECT_EQ(early.get().size(), late.get().size());
  // Without the filter the samples are the caller's own.
  mm::BackgroundTriangulation plain(samples, angles, false);
  EXPECT_EQ(&plain.samples(), &samples);
}

TEST(HiddenReturns, TheBoxKeepsItsDepthInTheDenseModel) {
  const Occluders box{{{-2.0, 2.0, -0.1, 1.5}}};
  const std::vector<Eigen::Vector3d> points = scan(box, kScannerAbove, 0.4);
  mm::DepthCompletionParams params;
  params.model = mm::DepthModel::kGroundGp;
  params.ground.input = mm::GroundPriorParams::Input::kDense;
  params.ground.camera_height = 100.0;  // no ground in view
  mm::setScanOrigin(kScannerAbove, params.ground);
  const auto wrong_pixels = [&](bool drop) {
    params.ground.drop_hidden_returns = drop;
    mm::DepthCompleter completer(2);
    const mm::DepthMap map = completer.complete(points, smallCamera(), {smallImage(), 1}, params);
    // The stats say how many returns were left out (-1: the filter did not run).
    if (drop) {
      EXPECT_GT(map.stats.ground_hidden_returns, 100);
    } else {
      EXPECT_EQ(map.stats.ground_hidden_returns, -1);
    }
    // The box's pixels (rows 58-90, columns 40-120), away from its outline, that got the wall's
    // depth.
    int wrong = 0;
    for (int v = 60; v < 88; ++v) {
      for (int u = 44; u < 117; ++u)
        wrong += map.depth[std::size_t(v) * 160 + u] > 2.0 * kBoxZ;
    }
    return wrong;
  };
  const int with_hidden = wrong_pixels(false);
  EXPECT_GT(with_hidden, 50);  // the bleeding this is about
  EXPECT_EQ(wrong_pixels(true), 0);
}
