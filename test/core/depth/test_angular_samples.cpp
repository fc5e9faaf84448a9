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
