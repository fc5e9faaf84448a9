// The camera model: ROS distortion models read, projection through the lens and its inverse.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "../input_error.hpp"
#include "multimodal_nvs/core/common/camera.hpp"

namespace mm = multimodal_nvs;
using mm::LensDistortion;
using mm::test::inputErrorOf;

namespace {

// The plumb_bob camera of ../shared/data/distorted_camera (a 1920x1200 automotive camera).
const std::vector<double> kPlumbBob = {-0.10814499855041504, 0.1386680006980896,
                                       -0.0037975700106471777, -0.004841269925236702, 0.0};
// A wide-angle rational_polynomial lens (OpenCV's 8-coefficient model).
const std::vector<double> kRational = {0.8, 0.15, 0.001, -0.002, 0.003, 1.1, 0.35, 0.02};

mm::PinholeIntrinsics cameraWith(const LensDistortion& d) {
  return {2109.75, 2071.72, 949.828, 576.237, d};
}

}  // namespace

TEST(LensDistortion, ReadsTheRosModels) {
  const auto plumb = LensDistortion::fromRos("plumb_bob", kPlumbBob, "info");
  EXPECT_EQ(plumb.model, LensDistortion::Model::kPlumbBob);
  EXPECT_EQ(plumb.coefficientCount(), 5);
  EXPECT_EQ(plumb.rosName(), "plumb_bob");
  EXPECT_EQ(plumb.coefficients[1], kPlumbBob[1]);
  EXPECT_GT(plumb.monotone_radius, 1.0);
  const auto rational = LensDistortion::fromRos("rational_polynomial", kRational, "info");
  EXPECT_EQ(rational.model, LensDistortion::Model::kRationalPolynomial);
  EXPECT_EQ(rational.coefficients[7], kRational[7]);
}

TEST(LensDistortion, ZeroCoefficientsArePinhole) {
  // What drivers of rectified cameras publish: the pinhole code paths must be taken.
  EXPECT_FALSE(LensDistortion::fromRos("plumb_bob", std::vector<double>(5, 0.0), "i").any());
  EXPECT_FALSE(LensDistortion::fromRos("plumb_bob", {}, "i").any());
  EXPECT_FALSE(LensDistortion::fromRos("", {}, "i").any());
  EXPECT_FALSE(
      LensDistortion::fromRos("rational_polynomial", std::vector<double>(8, 0.0), "i").any());
}

TEST(LensDistortion, UnsupportedModelsNameTheModel) {
  EXPECT_NE(inputErrorOf([] {
              LensDistortion::fromRos("equidistant", {0.1, 0.01, 0.0, 0.0}, "cam.yaml");
            }).find("cam.yaml: distortion model 'equidistant' is not supported"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { LensDistortion::fromRos("fisheye42", {}, "x"); }).find("fisheye42"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              LensDistortion::fromRos("plumb_bob", {0.1, 0.2, 0, 0}, "x");
            }).find("'plumb_bob' needs 5 coefficients in D, got 4"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              LensDistortion::fromRos("rational_polynomial", kPlumbBob, "x");
            }).find("needs 8"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { LensDistortion::fromRos("", {0.1}, "x"); }).find("(none)"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              LensDistortion::fromRos("plumb_bob", {NAN, 0, 0, 0, 0}, "x");
            }).find("non-finite D[0]"),
            std::string::npos);
  // A lens that folds back right away is no usable model.
  EXPECT_NE(inputErrorOf([] {
              LensDistortion::fromRos("plumb_bob", {-500, 0, 0, 0, 0}, "x");
            }).find("folds back"),
            std::string::npos);
}

TEST(PinholeIntrinsics, ProjectionAndRaysInvertEachOther) {
  for (const auto& d : {LensDistortion::fromRos("plumb_bob", kPlumbBob, "p"),
                        LensDistortion::fromRos("rational_polynomial", kRational, "r")}) {
    const mm::PinholeIntrinsics k = cameraWith(d);
    std::vector<Eigen::Vector2d> pixels, expected;
    for (double u : {0.0, 300.0, 949.8, 1500.0, 1919.0}) {
      for (double v : {0.0, 576.2, 1199.0}) {
        pixels.emplace_back(u, v);
        expected.emplace_back(u, v);
      }
    }
    k.normalisedRays(pixels);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      double u = 0, v = 0;
      ASSERT_TRUE(k.project(pixels[i].x() * 7.0, pixels[i].y() * 7.0, 7.0, &u, &v));
      EXPECT_NEAR(u, expected[i].x(), 1e-6) << d.rosName() << " pixel " << i;
      EXPECT_NEAR(v, expected[i].y(), 1e-6) << d.rosName() << " pixel " << i;
    }
  }
}

TEST(PinholeIntrinsics, DistortionMovesCornersNotTheCentre) {
  const mm::PinholeIntrinsics k = cameraWith(LensDistortion::fromRos("plumb_bob", kPlumbBob, "p"));
  const mm::PinholeIntrinsics pinhole = k.pinhole();
  EXPECT_FALSE(pinhole.distortion.any());
  double u = 0, v = 0, pu = 0, pv = 0;
  ASSERT_TRUE(k.project(0.0, 0.0, 5.0, &u, &v));
  EXPECT_DOUBLE_EQ(u, k.cx);
  EXPECT_DOUBLE_EQ(v, k.cy);
  ASSERT_TRUE(k.project(2.0, 1.2, 5.0, &u, &v));  // towards the lower right corner
  ASSERT_TRUE(pinhole.project(2.0, 1.2, 5.0, &pu, &pv));
  EXPECT_GT(std::hypot(u - pu, v - pv), 5.0);
  // Scaling keeps the distortion (it lives in normalised coordinates).
  EXPECT_EQ(k.scaledTo(1200, 1920, 600, 960).distortion, k.distortion);
}

TEST(PinholeIntrinsics, ProjectionRefusesRaysPastTheFold) {
  // k1 < 0 alone folds at r = 1/sqrt(3 |k1|): the far ray would land back inside the image.
  const mm::PinholeIntrinsics k =
      cameraWith(LensDistortion::fromRos("plumb_bob", {-0.3, 0, 0, 0, 0}, "p"));
  EXPECT_NEAR(k.distortion.monotone_radius, 1.0 / std::sqrt(0.9), 2e-3);
  double u = 0, v = 0;
  EXPECT_TRUE(k.project(0.5, 0.0, 1.0, &u, &v));
  EXPECT_FALSE(k.project(3.0, 0.0, 1.0, &u, &v));
}

// A lens that never folds (no finite radius) still overflows far out: a camera_info whose
// principal point was ~1e96 (found by fuzz_camera_info) put its image corners' rays at ~1e92, where
// r^4 is infinite and an unused coefficient times it is NaN. Such a direction is refused.
TEST(LensDistortion, RefusesDirectionsWhereThePolynomialOverflows) {
  const LensDistortion lens =
      LensDistortion::fromRos("plumb_bob", {-0.108145, 0.138668, -0.0037976, -0.0048413, 0.0}, "p");
  ASSERT_FALSE(std::isfinite(lens.monotone_radius));
  double xd = 0, yd = 0;
  EXPECT_TRUE(lens.distort(0.3, -0.2, &xd, &yd));
  EXPECT_FALSE(lens.distort(-4.5e92, -2.7e-1, &xd, &yd));
  const mm::PinholeIntrinsics k(2109.75, 2071.72, 9.4e95, 576.237, lens);
  double u = 0, v = 0;
  EXPECT_FALSE(k.project(-4.5e92, -0.27, 1.0, &u, &v));
}

TEST(LensDistortion, MonotoneRadiusHoldsInEveryDirectionAndIsTight) {
  // Tangential terms make the fold direction dependent; the radius must hold in all of them (here
  // 3600, many between any fixed sample of directions) and be reached in the worst one.
  const std::vector<std::vector<double>> lenses = {
      {-0.3, 0.0, 0.02, -0.03, 0.0}, {-0.2, 0.01, -0.05, 0.01, 0.0}, kPlumbBob};
  for (const std::vector<double>& d : lenses) {
    const LensDistortion lens = LensDistortion::fromRos("plumb_bob", d, "p");
    ASSERT_TRUE(std::isfinite(lens.monotone_radius) || d == kPlumbBob);
    LensDistortion unlimited = lens;  // the raw model, also past the fold
    unlimited.monotone_radius = std::numeric_limits<double>::infinity();
    const double limit = std::min(lens.monotone_radius, 10.0);
    double worst_fold = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3600; ++i) {
      const double a = 2.0 * M_PI * i / 3600.0, c = std::cos(a), s = std::sin(a);
      double previous = 0.0;
      for (double r = 1e-3; r <= limit + 0.05 && r <= 10.0; r += 1e-3) {
        double xd = 0, yd = 0;
        ASSERT_TRUE(unlimited.distort(r * c, r * s, &xd, &yd));
        const double along = xd * c + yd * s;
        if (!(along > previous)) {
          ASSERT_GT(r, limit) << "folds inside the radius at angle " << a;
          worst_fold = std::min(worst_fold, r);
          break;
        }
        previous = along;
      }
    }
    if (std::isfinite(lens.monotone_radius)) {
      EXPECT_NEAR(worst_fold, lens.monotone_radius, 3e-3);
    }
  }
}
