// The per-pixel step: single precision (ground_gp's residual GP) against double on random sets of 1
// to 12 returns within the 2 degree radius (ground_gp's residual amplitude, the package's noise,
// pixels across and beyond the set, blocks longer than one stack block), and several runs of
// pixels in one call against one call per run.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/gp/gp_prediction.hpp"
#include "multimodal_nvs/core/depth/gp/local_gp.hpp"

namespace mm = multimodal_nvs;

namespace {

TEST(GpPredictionPrecision, SingleAgreesWithDoubleToFloatRounding) {
  mm::DepthCompletionParams params;
  params.gp.amplitude = params.ground.residual_amplitude;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> angle(-2.0f, 2.0f);
  std::uniform_real_distribution<double> depth(-8.0, 0.0);  // residuals are clipped to <= 0
  mm::LocalGp gp(params.gp);
  const double prior =
      params.gp.amplitude * params.gp.amplitude + params.gp.noise * params.gp.noise;
  int compared = 0;
  for (int n = 1; n <= 12; ++n) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<float> az(n), el(n);
      std::vector<double> y(n);
      for (int i = 0; i < n; ++i) {
        az[i] = angle(rng);
        el[i] = angle(rng);
        y[i] = depth(rng);
      }
      gp.setData(az.data(), el.data(), y.data(), n);
      const double l = gp.searchLengthScale();
      std::vector<double> factor, beta;
      ASSERT_TRUE(gp.posterior(l, factor, beta));
      const int pixels = 150;  // more than one block of the per-pixel step
      std::vector<float> paz(pixels), pel(pixels);
      for (int p = 0; p < pixels; ++p) {
        paz[p] = 1.5f * angle(rng);
        pel[p] = 1.5f * angle(rng);
      }
      std::vector<float> mean64(pixels), var64(pixels), mean32(pixels), var32(pixels);
      mm::predictFromFactor(factor.data(), beta.data(), az.data(), el.data(), n, l, params.gp,
                            paz.data(), pel.data(), pixels, 3.0, mean64.data(), var64.data(),
                            mm::PredictionPrecision::kDouble);
      mm::predictFromFactor(factor.data(), beta.data(), az.data(), el.data(), n, l, params.gp,
                            paz.data(), pel.data(), pixels, 3.0, mean32.data(), var32.data(),
                            mm::PredictionPrecision::kSingle);
      for (int p = 0; p < pixels; ++p) {
        ASSERT_TRUE(std::isfinite(mean32[p]) && std::isfinite(var32[p]));
        EXPECT_NEAR(mean32[p], mean64[p], 1e-4 * (1.0 + std::abs(mean64[p])))
            << "n " << n << " pixel " << p;
        EXPECT_NEAR(var32[p], var64[p], 1e-5 * prior) << "n " << n << " pixel " << p;
        EXPECT_GE(var32[p], 0.0f);
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 12 * 20 * 150);
}

// Several runs in one call (a set's segments in a band of rows) give every pixel exactly what one
// call per run gives: runs of 0 to 70 pixels, so that blocks span several runs and runs span
// blocks, in both precisions and for fixed and general set sizes.
TEST(GpPredictionPrecision, RunsInOneCallEqualOneCallPerRun) {
  mm::DepthCompletionParams params;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> angle(-2.0f, 2.0f);
  std::uniform_real_distribution<double> depth(5.0, 40.0);
  std::uniform_int_distribution<int> run_length(0, 70);
  mm::LocalGp gp(params.gp);
  int compared = 0;
  for (int n : {1, 3, 6, 9}) {
    std::vector<float> az(n), el(n);
    std::vector<double> y(n);
    for (int i = 0; i < n; ++i) {
      az[i] = angle(rng);
      el[i] = angle(rng);
      y[i] = depth(rng) - 20.0;
    }
    gp.setData(az.data(), el.data(), y.data(), n);
    const double l = gp.searchLengthScale();
    std::vector<double> factor, beta;
    ASSERT_TRUE(gp.posterior(l, factor, beta));
    for (auto precision : {mm::PredictionPrecision::kDouble, mm::PredictionPrecision::kSingle}) {
      std::vector<int> lengths(9);
      int pixels = 0;
      for (int& length : lengths) {
        length = run_length(rng);
        pixels += length;
      }
      std::vector<float> paz(pixels), pel(pixels);
      for (int p = 0; p < pixels; ++p) {
        paz[p] = 1.5f * angle(rng);
        pel[p] = 1.5f * angle(rng);
      }
      std::vector<float> mean_runs(pixels, -1.0f), var_runs(pixels, -1.0f);
      std::vector<float> mean_each(pixels, -2.0f), var_each(pixels, -2.0f);
      std::vector<mm::PixelRun> runs;
      int start = 0;
      for (int length : lengths) {
        runs.push_back({paz.data() + start, pel.data() + start, mean_runs.data() + start,
                        var_runs.data() + start, length});
        mm::predictFromFactor(factor.data(), beta.data(), az.data(), el.data(), n, l, params.gp,
                              paz.data() + start, pel.data() + start, length, 20.0,
                              mean_each.data() + start, var_each.data() + start, precision);
        start += length;
      }
      mm::predictFromFactor(factor.data(), beta.data(), az.data(), el.data(), n, l, params.gp,
                            runs.data(), static_cast<int>(runs.size()), 20.0, precision);
      for (int p = 0; p < pixels; ++p) {
        ASSERT_EQ(mean_runs[p], mean_each[p]) << "n " << n << " pixel " << p;
        ASSERT_EQ(var_runs[p], var_each[p]) << "n " << n << " pixel " << p;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 100);
}

}  // namespace
