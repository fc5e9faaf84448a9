// StrideGrid: which stride maps a full image onto a depth raster, and the grid's intrinsics.
#include <gtest/gtest.h>

#include "multimodal_nvs/core/common/stride_grid.hpp"

namespace mm = multimodal_nvs;

TEST(StrideGrid, GridOfSizeIsTheSmallestStrideWithCeilRowsAndCols) {
  const auto same = mm::strideGridOfSize({120, 160}, {120, 160});
  ASSERT_TRUE(same);
  EXPECT_EQ(same->stride, 1);
  // ceil(121 / 2) x ceil(161 / 2): the last row and column of an odd size still count.
  const auto two = mm::strideGridOfSize({121, 161}, {61, 81});
  ASSERT_TRUE(two);
  EXPECT_EQ(*two, (mm::StrideGrid{{121, 161}, 2}));
  const auto four = mm::strideGridOfSize({1216, 1936}, {304, 484});
  ASSERT_TRUE(four);
  EXPECT_EQ(four->stride, 4);
  // 2x2 is ceil(H/s) x ceil(W/s) for s = 60 and 61 alike: the smallest wins.
  EXPECT_EQ(mm::strideGridOfSize({120, 120}, {2, 2})->stride, 60);
  EXPECT_EQ(mm::strideGridOfSize({64, 64}, {1, 1})->stride, 64);
  EXPECT_FALSE(mm::strideGridOfSize({65, 65}, {1, 1}));  // would need s = 65 > 64
  EXPECT_FALSE(mm::strideGridOfSize({120, 160}, {50, 70}));
  EXPECT_FALSE(mm::strideGridOfSize({120, 160}, {60, 160}));  // one stride for both axes
}

TEST(StrideGrid, IntrinsicsAreDividedOnTheGridAndMultipliedBack) {
  const mm::StrideGrid grid{{120, 160}, 4};
  const mm::PinholeIntrinsics k{400.0, 300.0, 80.0, 60.0};
  const mm::PinholeIntrinsics g = grid.gridIntrinsics(k);
  EXPECT_DOUBLE_EQ(g.fx, 100.0);
  EXPECT_DOUBLE_EQ(g.fy, 75.0);
  EXPECT_DOUBLE_EQ(g.cx, 20.0);  // no half-pixel shift: grid pixel 0 is image pixel 0
  EXPECT_DOUBLE_EQ(g.cy, 15.0);
  const mm::PinholeIntrinsics back = grid.imageIntrinsics(g);
  EXPECT_DOUBLE_EQ(back.fx, k.fx);
  EXPECT_DOUBLE_EQ(back.fy, k.fy);
  EXPECT_DOUBLE_EQ(back.cx, k.cx);
  EXPECT_DOUBLE_EQ(back.cy, k.cy);
  const mm::PinholeIntrinsics same = mm::StrideGrid{{120, 160}, 1}.gridIntrinsics(k);
  EXPECT_EQ(same.fx, k.fx);
  EXPECT_EQ(same.cy, k.cy);
}
