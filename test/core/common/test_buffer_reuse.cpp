// The one rule for freeing a reused buffer (the depth workspace and the recycled ROS messages).
#include <gtest/gtest.h>

#include "multimodal_nvs/core/common/buffer_reuse.hpp"

namespace mm = multimodal_nvs;

TEST(BufferReuse, FreesOnlyFarLargerBuffers) {
  const std::size_t slack = std::size_t(1) << 16;
  EXPECT_FALSE(mm::capacityFarExceeds(0, 0));
  EXPECT_FALSE(mm::capacityFarExceeds(slack, 0));
  EXPECT_TRUE(mm::capacityFarExceeds(slack + 1, 0));
  EXPECT_FALSE(mm::capacityFarExceeds(4 * 1000000 + slack, 1000000));
  EXPECT_TRUE(mm::capacityFarExceeds(4 * 1000000 + slack + 1, 1000000));
}
