// forEachSetByte visits exactly the set bytes of a mask, in order, whatever its length and
// alignment, sparse or dense.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "multimodal_nvs/core/common/mask_scan.hpp"

namespace mm = multimodal_nvs;

TEST(MaskScan, VisitsExactlyTheSetBytesInOrder) {
  std::mt19937 rng(5);
  int cases = 0;
  for (int count = 0; count <= 70; ++count) {
    for (double density : {0.0, 0.02, 0.3, 1.0}) {
      for (int offset = 0; offset < 3; ++offset) {  // the mask need not start 8-byte aligned
        std::vector<std::uint8_t> buffer(count + offset);
        std::bernoulli_distribution set(density);
        std::uniform_int_distribution<int> value(1, 255);
        std::vector<int> want;
        for (int i = 0; i < count; ++i) {
          if (set(rng)) {
            buffer[offset + i] = static_cast<std::uint8_t>(value(rng));
            want.push_back(i);
          }
        }
        std::vector<int> got;
        mm::forEachSetByte(buffer.data() + offset, count, [&](int i) { got.push_back(i); });
        ASSERT_EQ(got, want) << "count " << count << " density " << density;
        ++cases;
      }
    }
  }
  EXPECT_EQ(cases, 71 * 4 * 3);
}
