// The top of the band of elevations a sensor's returns cover.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "multimodal_nvs/core/depth/return_band.hpp"

namespace mm = multimodal_nvs;

// 100 elevations 0..99 degrees in shuffled order: the top 2 % (98 and 99) lie above the band, so
// its top is 97; a share of 0 gives the highest return, and no returns no band.
TEST(ReturnBand, TopLeavesTheHighestShareAboveIt) {
  std::vector<float> elevations;
  for (int i = 0; i < 100; ++i)
    elevations.push_back(float((i * 37) % 100));
  EXPECT_EQ(mm::returnBandTop(elevations), 97.0f);
  EXPECT_EQ(mm::returnBandTop(elevations, 0.0), 99.0f);
  EXPECT_EQ(mm::returnBandTop(elevations, 0.5), 49.0f);
  // Fewer than 50 returns: 2 % of them is no return, the band reaches the highest.
  EXPECT_EQ(mm::returnBandTop({-3.0f, 1.5f, -0.5f}), 1.5f);
  // A share beyond 1 is the lowest return, not a read past the end.
  EXPECT_EQ(mm::returnBandTop({-3.0f, 1.5f, -0.5f}, 5.0), -3.0f);
  EXPECT_TRUE(std::isnan(mm::returnBandTop({})));
}
