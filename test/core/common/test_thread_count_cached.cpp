// ThreadCountCached: one engine per thread count, kept while the count stays.
#include <gtest/gtest.h>

#include "multimodal_nvs/core/common/thread_count_cached.hpp"

namespace mm = multimodal_nvs;

namespace {

struct CountingEngine {
  explicit CountingEngine(int threads) : threads(threads) { ++built; }
  int threads;
  static int built;
};
int CountingEngine::built = 0;

}  // namespace

TEST(ThreadCountCached, BuildsAgainOnlyWhenTheThreadCountChanges) {
  CountingEngine::built = 0;
  mm::ThreadCountCached<CountingEngine> cache;
  CountingEngine* first = &cache.forThreads(2);
  EXPECT_EQ(first->threads, 2);
  EXPECT_EQ(&cache.forThreads(2), first);
  EXPECT_EQ(CountingEngine::built, 1);
  EXPECT_EQ(cache.forThreads(3).threads, 3);
  EXPECT_EQ(CountingEngine::built, 2);
  EXPECT_EQ(cache.forThreads(0).threads, 0);  // 0 (hardware concurrency) is a count like any other
  EXPECT_EQ(CountingEngine::built, 3);
}
