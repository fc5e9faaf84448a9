// ThreadPool: every index runs exactly once, and an exception thrown on any thread reaches the
// caller instead of terminating the process (the depth nodelet catches std::bad_alloc from there).
#include <gtest/gtest.h>

#include <atomic>
#include <new>
#include <stdexcept>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace mm = multimodal_nvs;

TEST(ThreadPool, RunsEveryIndexExactlyOnce) {
  for (int threads : {1, 2, 5}) {
    mm::ThreadPool pool(threads);
    std::vector<std::atomic<int>> runs(1000);
    pool.parallelFor(
        static_cast<long long>(runs.size()),
        [&](long long i, int worker) {
          EXPECT_GE(worker, 0);
          EXPECT_LT(worker, pool.size());
          ++runs[i];
        },
        7);
    for (const auto& r : runs)
      EXPECT_EQ(r.load(), 1);
  }
}

TEST(ThreadPool, AnExceptionOnAnyThreadIsRethrownToTheCallerAndThePoolStaysUsable) {
  for (int threads : {1, 2, 4}) {
    mm::ThreadPool pool(threads);
    // Thrown late so that, with several threads, it is usually a worker that throws.
    EXPECT_THROW(pool.parallelFor(400,
                                  [](long long i, int) {
                                    if (i == 397) throw std::bad_alloc();
                                  }),
                 std::bad_alloc);
    EXPECT_THROW(pool.parallelFor(400,
                                  [](long long i, int) {
                                    if (i % 50 == 3) throw std::runtime_error("every 50th");
                                  }),
                 std::runtime_error);
    std::atomic<long long> sum{0};
    pool.parallelFor(100, [&](long long i, int) { sum += i; });
    EXPECT_EQ(sum.load(), 4950) << threads << " threads";
  }
}
