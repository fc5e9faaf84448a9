// Rows as lanes: the AVX 8x8 transpose gives what the plain loop gives, and rows go into lanes and
// back unchanged for full and partial blocks and for widths that are not a multiple of eight.
#include <gtest/gtest.h>

#include <vector>

#include "multimodal_nvs/core/common/lane_transpose.hpp"
#include "multimodal_nvs/core/common/simd_buffer.hpp"

namespace mm = multimodal_nvs;

TEST(LaneTranspose, Transpose8x8AgreesWithThePlainLoop) {
  std::vector<float> source(8 * 11);
  for (std::size_t i = 0; i < source.size(); ++i)
    source[i] = 0.5f * static_cast<float>(i) - 7.0f;
  std::vector<float> fast(8 * 9, -1.0f), plain(8 * 9, -1.0f);
  mm::transpose8x8(source.data(), 11, fast.data(), 9);
  mm::transpose8x8Portable(source.data(), 11, plain.data(), 9);
  EXPECT_EQ(fast, plain);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      EXPECT_EQ(fast[i * 9 + j], source[j * 11 + i]) << i << ", " << j;
  EXPECT_EQ(fast[8], -1.0f) << "wrote outside the block";
}

TEST(LaneTranspose, RowsGoIntoLanesAndBackUnchanged) {
  const int cols = 21, stride = 23;
  for (int row_count : {8, 5, 1}) {
    std::vector<float> rows(8 * stride);
    for (std::size_t i = 0; i < rows.size(); ++i)
      rows[i] = static_cast<float>(i) + 0.25f;
    mm::SimdVector<float> storage(std::size_t(cols) * mm::kLaneCount, -3.0f);
    mm::Lanes* lanes = reinterpret_cast<mm::Lanes*>(storage.data());
    mm::rowsToLanes(rows.data(), stride, row_count, cols, lanes);
    for (int c = 0; c < cols; ++c) {
      for (int k = 0; k < mm::kLaneCount; ++k) {
        const float want = k < row_count ? rows[k * stride + c] : 0.0f;
        ASSERT_EQ(lanes[c][k], want) << "column " << c << ", lane " << k << ", rows " << row_count;
      }
    }
    for (mm::Lanes* l = lanes; l != lanes + cols; ++l)
      *l = *l * 2.0f;
    mm::lanesToRows(lanes, row_count, cols, rows.data(), stride);
    for (int r = 0; r < 8; ++r) {
      for (int c = 0; c < stride; ++c) {
        const float original = static_cast<float>(r * stride + c) + 0.25f;
        const bool written = r < row_count && c < cols;
        ASSERT_EQ(rows[r * stride + c], written ? 2.0f * original : original)
            << "row " << r << ", column " << c << ", rows " << row_count;
      }
    }
  }
}
