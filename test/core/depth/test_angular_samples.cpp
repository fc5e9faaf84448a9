// The angular-domain helpers shared by the models: bounding box, usable samples, and the "no
// prediction" starting state of a model's output.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"

namespace mm = multimodal_nvs;

TEST(AngularSamples, BoundingBoxHoldsEverySample) {
  const std::vector<mm::AngularSample> samples = {
      {-3.5f, 1.0f, 10.0f}, {2.0f, -4.25f, 5.0f}, {0.5f, 7.0f, 20.0f}};
  const mm::AngularBox box = mm::boundingBox(samples);
  EXPECT_EQ(box.az_min, -3.5f);
  EXPECT_EQ(box.az_max, 2.0f);
  EXPECT_EQ(box.el_min, -4.25f);
  EXPECT_EQ(box.el_max, 7.0f);
}

TEST(AngularSamples, BoundingBoxOfNothingIsEmpty) {
  const mm::AngularBox box = mm::boundingBox({});
  EXPECT_TRUE(std::isinf(box.az_min) && box.az_min > 0);
  EXPECT_TRUE(std::isinf(box.az_max) && box.az_max < 0);
  EXPECT_GT(box.el_min, box.el_max);
}

TEST(AngularSamples, UsableSamplesDropNonFiniteAndBehindCamera) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<mm::AngularSample> samples = {{1.0f, 1.0f, 5.0f},
                                                  {nan, 0.0f, 5.0f},
                                                  {0.0f, 0.0f, -2.0f},
                                                  {0.0f, 0.0f, 0.0f},
                                                  {2.0f, -1.0f, 8.0f}};
  const std::vector<mm::AngularSample> usable = mm::usableSamples(samples);
  ASSERT_EQ(usable.size(), 2u);
  EXPECT_EQ(usable[0].depth, 5.0f);  // original order kept
  EXPECT_EQ(usable[1].depth, 8.0f);
}

// Points behind the camera (z <= 0) never become samples (their depth would be <= 0 and their
// direction 90 deg or more off the axis); the others keep their order, with or without a pool,
// and non-finite points are counted.
TEST(AngularSamples, ConversionSkipsPointsBehindTheCamera) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 40000; ++i) {  // more than one chunk of the pooled conversion
    const double a = 0.001 * i;
    points.emplace_back(10.0 * std::sin(a), 0.5 - 0.0001 * i, 10.0 * std::cos(a));
  }
  points.emplace_back(inf, 0.0, 1.0);
  points.emplace_back(1.0, 0.0, 0.0);  // in the camera plane
  std::size_t dropped = 0;
  const std::vector<mm::AngularSample> serial = mm::toAngularSamples(points, &dropped);
  EXPECT_EQ(dropped, 1u);
  std::size_t in_front = 0;
  for (const Eigen::Vector3d& p : points)
    in_front += p.allFinite() && p.z() > 0.0;
  ASSERT_EQ(serial.size(), in_front);
  std::size_t k = 0;
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite() || !(p.z() > 0.0)) continue;
    EXPECT_EQ(serial[k].depth, static_cast<float>(p.z()));
    EXPECT_EQ(serial[k].azimuth_deg,
              static_cast<float>(std::atan2(p.x(), p.z()) * (180.0 / 3.14159265358979323846)));
    EXPECT_LT(std::abs(serial[k].azimuth_deg), 90.0f);
    ++k;
  }
  mm::ThreadPool pool(3);
  const std::vector<mm::AngularSample> pooled = mm::toAngularSamples(points, nullptr, &pool);
  ASSERT_EQ(pooled.size(), serial.size());
  for (std::size_t i = 0; i < serial.size(); ++i) {
    EXPECT_EQ(pooled[i].azimuth_deg, serial[i].azimuth_deg);
    EXPECT_EQ(pooled[i].elevation_deg, serial[i].elevation_deg);
    EXPECT_EQ(pooled[i].depth, serial[i].depth);
  }
}

// The azimuth pre-filter of the projection passes: every direction that lands in the columns
// passes (at any elevation), those a degree outside do not, and with a lens model (whose column
// also depends on the elevation) only the front half is promised.
TEST(AngularSamples, AzimuthWindowHoldsEveryDirectionInTheColumns) {
  mm::PinholeIntrinsics k(1500.0, 1500.0, 968.0, 608.0);  // VoD-like, 1936 px wide
  const mm::AzimuthWindow window = mm::azimuthWindow(k, -0.5, 1935.5);
  int inside = 0;
  for (double az = -60.0; az <= 60.0; az += 0.01) {
    for (const double el : {-30.0, 0.0, 25.0}) {
      double u = 0.0, v = 0.0;
      ASSERT_TRUE(mm::angularToPixel(k, az, el, &u, &v));
      if (u >= -0.5 && u <= 1935.5) {
        EXPECT_TRUE(window.contains(az)) << az;
        ++inside;
      }
    }
    if (az < window.min_deg - 1.0 || az > window.max_deg + 1.0) {
      double u = 0.0, v = 0.0;
      mm::angularToPixel(k, az, 0.0, &u, &v);
      EXPECT_TRUE(u < -0.5 || u > 1935.5) << az;
    }
  }
  EXPECT_GT(inside, 3 * 5000);  // the 64-degree field of view was sampled
  EXPECT_NEAR(window.max_deg - window.min_deg, 2.0 * std::atan(968.0 / 1500.0) * 180.0 / M_PI,
              0.01);
  EXPECT_FALSE(window.contains(std::numeric_limits<double>::quiet_NaN()));
  k.distortion = mm::LensDistortion::fromRos("plumb_bob", {-0.1, 0.1, 0.0, 0.0, 0.0}, "test");
  const mm::AzimuthWindow lens = mm::azimuthWindow(k, -0.5, 1935.5);
  EXPECT_EQ(lens.min_deg, -90.0);
  EXPECT_EQ(lens.max_deg, 90.0);
}

TEST(PixelPredictions, SetNoPredictionResizesAndClears) {
  mm::PixelPredictions out;
  out.mean.assign(3, 1.0f);
  out.variance.assign(3, 2.0f);
  mm::StrideGrid grid;
  grid.image = {5, 4};  // 3 x 2 grid pixels at stride 2
  grid.stride = 2;
  mm::setNoPrediction(grid, out);
  ASSERT_EQ(out.mean.size(), 6u);
  ASSERT_EQ(out.variance.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_TRUE(std::isnan(out.mean[i]));
    EXPECT_EQ(out.variance[i], mm::kNoPrediction);
  }
}
