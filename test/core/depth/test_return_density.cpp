// How densely the returns cover the view, and image_guided's prior weight that follows from it.
#include <gtest/gtest.h>

#include <cmath>

#include "multimodal_nvs/core/depth/return_density.hpp"

namespace mm = multimodal_nvs;

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;
}

// A 1x1 image with its principal point on the pixel's centre and unit focal lengths spans
// atan(0.5) to either side along both axes.
TEST(ReturnDensity, ViewIsThePinholesAngularExtentInBothAxes) {
  const double side = 2.0 * std::atan(0.5) * kRadToDeg;  // 53.13 degrees
  EXPECT_NEAR(mm::viewSquareDegrees({1.0, 1.0, 0.0, 0.0}, {1, 1}), side * side, 1e-9);
  // A principal point off-centre shifts the view, and the extent is the sum of both sides.
  const double az = (std::atan(1.5 / 1.0) + std::atan(0.5 / 1.0)) * kRadToDeg;
  const double el = (std::atan(0.5 / 2.0) + std::atan(0.5 / 2.0)) * kRadToDeg;
  EXPECT_NEAR(mm::viewSquareDegrees({1.0, 2.0, 0.0, 0.0}, {1, 2}), az * el, 1e-9);
  // View-of-Delft's camera (P2 of its calibration files, 1936x1216): 2,912 square degrees.
  EXPECT_NEAR(
      mm::viewSquareDegrees({1495.468642, 1495.468642, 961.272442, 624.89592}, {1216, 1936}),
      2912.6, 0.1);
}

TEST(ReturnDensity, ReturnsPerSquareDegreeAndZeroForNoView) {
  const mm::PinholeIntrinsics k{1.0, 1.0, 0.0, 0.0};
  const double area = mm::viewSquareDegrees(k, {1, 1});
  EXPECT_DOUBLE_EQ(mm::returnDensity(10, k, {1, 1}), 10.0 / area);
  EXPECT_EQ(mm::returnDensity(10, k, {0, 1}), 0.0);
  EXPECT_EQ(mm::returnDensity(10, {0.0, 1.0, 0.0, 0.0}, {1, 1}), 0.0);
}

TEST(ReturnDensity, PriorWeightIsProportionalWithinItsBoundsAndFixedWithoutAReference) {
  EXPECT_DOUBLE_EQ(mm::priorWeightForDensity(1e-3, 0.1, 0.1), 1e-3);
  EXPECT_DOUBLE_EQ(mm::priorWeightForDensity(1e-3, 0.5, 0.1), 5e-3);
  EXPECT_DOUBLE_EQ(mm::priorWeightForDensity(1e-3, 0.04, 0.1), 4e-4);
  EXPECT_DOUBLE_EQ(mm::priorWeightForDensity(1e-3, 0.0, 0.1), 1e-3 * mm::kMinPriorWeightFactor);
  EXPECT_DOUBLE_EQ(mm::priorWeightForDensity(1e-3, 50.0, 0.1), 1e-3 * mm::kMaxPriorWeightFactor);
  EXPECT_DOUBLE_EQ(mm::priorWeightForDensity(1e-3, 0.5, 0.0), 1e-3);
}
