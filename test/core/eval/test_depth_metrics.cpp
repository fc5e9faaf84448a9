// Depth metrics on hand-computed inputs, exact merging of sums, and both kinds of ground truth.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scene_fixtures.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/eval/depth_metrics.hpp"

namespace mm = multimodal_nvs;

TEST(DepthMetrics, HandComputedValues) {
  // Pixel 0: p 2 vs g 1; pixel 1: exact; pixel 2: not kept (-1); pixel 3: no ground truth.
  const float pred[] = {2.0f, 4.0f, -1.0f, 10.0f};
  const float gt[] = {1.0f, 4.0f, 3.0f, 0.0f};
  const mm::DepthErrorSums sums = mm::evaluateDepth(pred, nullptr, gt, 4, {});
  const mm::DepthMetrics m = mm::DepthMetrics::from(sums);
  EXPECT_EQ(m.gt_pixels, 3);
  EXPECT_EQ(m.count, 2);
  EXPECT_DOUBLE_EQ(m.mae, 0.5);
  EXPECT_DOUBLE_EQ(m.rmse, std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(m.rmse_log, std::sqrt(std::log(2.0) * std::log(2.0) / 2.0));
  EXPECT_DOUBLE_EQ(m.abs_rel, 0.5);
  EXPECT_DOUBLE_EQ(m.delta1, 0.5);  // 2/1 fails, 4/4 passes
  EXPECT_DOUBLE_EQ(m.coverage, 2.0 / 3.0);
}

TEST(DepthMetrics, DeltaThresholdIsStrict) {
  const float pred[] = {1.25f, 1.0f, 1.24f};
  const float gt[] = {1.0f, 1.25f, 1.0f};
  EXPECT_EQ(mm::evaluateDepth(pred, nullptr, gt, 3, {}).delta1, 1);
}

TEST(DepthMetrics, RangeCapIgnoresDeepTruthAndClipsPredictions) {
  const float pred[] = {100.0f, 5.0f};
  const float gt[] = {50.0f, 90.0f};
  mm::DepthEvaluationOptions options;
  options.max_depth = 60.0;
  const mm::DepthMetrics m =
      mm::DepthMetrics::from(mm::evaluateDepth(pred, nullptr, gt, 2, options));
  EXPECT_EQ(m.gt_pixels, 1);
  EXPECT_DOUBLE_EQ(m.mae, 10.0);  // 100 clipped to 60
}

TEST(DepthMetrics, MaskSelectsPixelsAndKeptNegativePredictionsAreClippedErrors) {
  const float pred[] = {-2.0f, 3.0f, 3.0f, NAN};
  const float gt[] = {1.0f, 3.0f, 6.0f, 2.0f};
  const std::uint8_t mask[] = {1, 1, 0, 1};
  const mm::DepthErrorSums s = mm::evaluateDepth(pred, mask, gt, 4, {});
  EXPECT_EQ(s.gt_pixels, 4);
  EXPECT_EQ(s.count, 2);  // the negative one counts (clipped to 1e-3), NaN and unmasked do not
  EXPECT_NEAR(s.abs_error, 1.0 - 1e-3, 1e-12);
  EXPECT_NEAR(s.sq_log_error, std::log(1e-3) * std::log(1e-3), 1e-9);
}

TEST(DepthMetrics, NoEvaluatedPixelGivesNaNNotZero) {
  const float pred[] = {-1.0f};
  const float gt[] = {5.0f};
  const mm::DepthMetrics m = mm::DepthMetrics::from(mm::evaluateDepth(pred, nullptr, gt, 1, {}));
  EXPECT_EQ(m.count, 0);
  EXPECT_TRUE(std::isnan(m.mae));
  EXPECT_DOUBLE_EQ(m.coverage, 0.0);
}

TEST(DepthMetrics, MergedSumsEqualTheSumsOfTheUnion) {
  const float pred[] = {2.0f, 4.0f, 7.0f, 1.0f, 9.0f};
  const float gt[] = {1.0f, 5.0f, 7.5f, 3.0f, 8.0f};
  mm::DepthErrorSums a = mm::evaluateDepth(pred, nullptr, gt, 2, {});
  a.merge(mm::evaluateDepth(pred + 2, nullptr, gt + 2, 3, {}));
  const mm::DepthErrorSums all = mm::evaluateDepth(pred, nullptr, gt, 5, {});
  EXPECT_EQ(a.count, all.count);
  EXPECT_EQ(a.delta1, all.delta1);
  EXPECT_DOUBLE_EQ(a.sq_error, all.sq_error);
  EXPECT_DOUBLE_EQ(a.sq_log_error, all.sq_log_error);
  EXPECT_DOUBLE_EQ(a.abs_rel, all.abs_rel);
}

TEST(DepthMetrics, SignedErrorsAtTruthFollowTheSamePixelsAndClippingAsTheSums) {
  // Truth pixels 0, 1, 3, 4 (2 has none, 5 is beyond the cap); 1 is not predicted (mask), 4 is
  // a kept negative depth (clipped to 1e-3), 3 is clipped to the cap.
  const float pred[] = {2.0f, 4.0f, 9.0f, 80.0f, -1.0f, 5.0f};
  const float gt[] = {1.0f, 4.0f, 0.0f, 50.0f, 2.0f, 70.0f};
  const std::uint8_t mask[] = {1, 0, 1, 1, 1, 1};
  mm::DepthEvaluationOptions options;
  options.max_depth = 60.0;
  const std::vector<float> e = mm::signedErrorsAtTruth(pred, mask, gt, 6, options);
  ASSERT_EQ(e.size(), 4u);  // one entry per ground-truth pixel, in grid order
  EXPECT_FLOAT_EQ(e[0], 1.0f);
  EXPECT_TRUE(std::isnan(e[1]));
  EXPECT_FLOAT_EQ(e[2], 10.0f);  // 80 clipped to 60
  EXPECT_FLOAT_EQ(e[3], 1e-3f - 2.0f);
  // Their mean absolute value is evaluateDepth's MAE.
  const mm::DepthErrorSums sums = mm::evaluateDepth(pred, mask, gt, 6, options);
  EXPECT_EQ(sums.gt_pixels, 4);
  double abs_sum = 0.0;
  for (float v : e)
    if (!std::isnan(v)) abs_sum += std::abs(double(v));
  EXPECT_NEAR(abs_sum, sums.abs_error, 1e-5);
}

TEST(DepthGroundTruth, ProjectedScanKeepsTheNearestReturnPerPixel) {
  const auto k = mm::test::smallCamera();
  const mm::StrideGrid grid{mm::test::smallImage(), 2};
  const std::vector<Eigen::Vector3d> points = {
      mm::test::pointOnPixelRay(k, 40, 30, 12.0),
      mm::test::pointOnPixelRay(k, 40.4, 30.2, 8.0),
      mm::test::pointOnPixelRay(k, 41.2, 30, 3.0),  // rounds to grid column 21, not 20
      mm::test::pointOnPixelRay(k, 500, 30, 3.0),   // outside
      {0.0, 0.0, -5.0},
      {NAN, 0.0, 4.0}};
  const std::vector<float> gt = mm::projectDepthGroundTruth(points, k, grid);
  ASSERT_EQ(gt.size(), static_cast<std::size_t>(grid.size()));
  EXPECT_FLOAT_EQ(gt[15 * grid.cols() + 20], 8.0f);
  EXPECT_FLOAT_EQ(gt[15 * grid.cols() + 21], 3.0f);
  int nonzero = 0;
  for (float z : gt)
    nonzero += z > 0.0f;
  EXPECT_EQ(nonzero, 2);
}

TEST(DepthGroundTruth, DenseTruthIsSampledOnTheStrideGrid) {
  const int h = 5, w = 7;
  std::vector<float> depth(h * w);
  for (int i = 0; i < h * w; ++i)
    depth[i] = float(i);
  depth[2 * w + 2] = NAN;
  const mm::StrideGrid grid{{h, w}, 2};
  const std::vector<float> gt = mm::sampleDenseGroundTruth(depth, h, w, grid);
  ASSERT_EQ(gt.size(), 12u);  // 3 x 4
  EXPECT_EQ(gt[0], 0.0f);     // depth 0 = no truth
  EXPECT_EQ(gt[1], 2.0f);
  EXPECT_EQ(gt[4], 14.0f);
  EXPECT_EQ(gt[5], 0.0f);  // NaN
  EXPECT_EQ(gt[11], float(4 * w + 6));
  EXPECT_THROW(mm::sampleDenseGroundTruth(depth, h, w, mm::StrideGrid{{h + 1, w}, 2}),
               mm::InputError);
}
