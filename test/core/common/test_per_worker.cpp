#include "multimodal_nvs/core/common/per_worker.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {
namespace {

std::uintptr_t addressOf(const void* p) {
  return reinterpret_cast<std::uintptr_t>(p);
}

TEST(PerWorker, EachWorkersObjectStartsOnLinesOfItsOwn) {
  // Objects far smaller than a cache line: side by side in a std::vector they would share one.
  PerWorker<int> counters(5, 7);
  ASSERT_EQ(counters.size(), 5);
  for (int w = 0; w < counters.size(); ++w) {
    EXPECT_EQ(counters[w], 7);
    EXPECT_EQ(addressOf(&counters[w]) % 128, 0u) << "worker " << w;
    if (w > 0) {
      EXPECT_GE(addressOf(&counters[w]) - addressOf(&counters[w - 1]), 128u);
    }
  }
}

TEST(PerWorker, WorkersAccumulateIntoTheirOwnObjects) {
  ThreadPool pool(3);
  PerWorker<std::vector<long long>> seen(pool.size());
  pool.parallelFor(1000, [&](long long i, int worker) { seen[worker].push_back(i); });
  std::vector<int> hits(1000, 0);
  for (int w = 0; w < seen.size(); ++w) {
    for (long long i : seen[w])
      ++hits[i];
  }
  for (int i = 0; i < 1000; ++i)
    EXPECT_EQ(hits[i], 1) << "index " << i;
}

}  // namespace
}  // namespace multimodal_nvs
