// The single-precision per-pixel step (ground_gp's residual GP) against the double one: random
// sets of 1 to 12 returns within the 2 degree radius, ground_gp's residual amplitude and the
// package's noise, pixels across and beyond the set, blocks longer than one stack block.
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

}  // namespace
