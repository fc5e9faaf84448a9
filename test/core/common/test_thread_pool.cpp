// ThreadPool: every index runs exactly once, loops right after one another and after idle gaps (the
// workers spinning, then asleep) see every worker's writes, and an exception thrown on any thread
// reaches the caller instead of terminating the process (the depth nodelet catches std::bad_alloc
// from there).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <new>
#include <stdexcept>
#include <thread>
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

TEST(ThreadPool, LoopsRightAfterOneAnotherAndAfterIdleGapsSeeEveryWorkersWrites) {
  mm::ThreadPool pool(3);
  std::vector<long long> values;
  for (int loop = 0; loop < 400; ++loop) {
    // Every 40th loop after a pause long enough for the workers to stop spinning and sleep; the
    // others back to back (the workers still spinning) or after a short serial step.
    if (loop % 40 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (loop % 3 == 1) std::this_thread::sleep_for(std::chrono::microseconds(20));
    const long long count = 1 + (loop % 9) * 37;  // from loops the caller finishes alone upwards
    values.assign(count, -1);
    pool.parallelFor(count, [&](long long i, int) { values[i] = loop * 1000 + i; });
    for (long long i = 0; i < count; ++i)
      ASSERT_EQ(values[i], loop * 1000 + i) << "loop " << loop << ", index " << i;
  }
}

TEST(ThreadPool, ShutsDownWhetherItsWorkersSpinOrSleep) {
  for (int pause_us : {0, 5000}) {
    mm::ThreadPool pool(4);
    std::atomic<long long> sum{0};
    pool.parallelFor(1000, [&](long long i, int) { sum += i; });
    std::this_thread::sleep_for(std::chrono::microseconds(pause_us));
    EXPECT_EQ(sum.load(), 499500);
  }  // the destructor joins: a hang here is a lost wake-up
}

// Without a pool every index runs in order on the calling thread as worker 0; with one, every
// index runs once.
TEST(ThreadPool, ParallelForOrInlineRunsEveryIndexOnceWithOrWithoutAPool) {
  std::vector<long long> order;
  mm::parallelForOrInline(nullptr, 5, [&](long long i, int worker) {
    EXPECT_EQ(worker, 0);
    order.push_back(i);
  });
  EXPECT_EQ(order, (std::vector<long long>{0, 1, 2, 3, 4}));
  mm::ThreadPool pool(2);
  std::vector<int> hits(100, 0);
  mm::parallelForOrInline(
      &pool, 100, [&](long long i, int) { ++hits[std::size_t(i)]; }, 7);
  EXPECT_EQ(hits, std::vector<int>(100, 1));
}
