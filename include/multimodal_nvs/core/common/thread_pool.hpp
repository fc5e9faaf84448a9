#pragma once
// A persistent thread pool for data-parallel loops whose results do not depend on thread count.
#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace multimodal_nvs {

/// A small persistent pool for data-parallel loops. Work is handed out in chunks through an atomic
/// counter; every index writes only its own outputs, so results never depend on the thread count
/// or on scheduling. The calling thread takes part, so a pool of size 1 runs everything inline.
/// One loop at a time: parallelFor must not be called from two threads at once, nor from inside a
/// body (each DepthCompleter / PointSplatter owns its pool, and each is used by one thread).
class ThreadPool {
 public:
  /// `threads` <= 0 means std::thread::hardware_concurrency().
  explicit ThreadPool(int threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }

  /// Calls body(index, worker) for every index in [0, count); `worker` in [0, size()) identifies
  /// the executing thread so that callers can keep per-thread scratch space. Blocks until done. If
  /// a body throws, the remaining indices are skipped and the first exception is rethrown here.
  void parallelFor(long long count, const std::function<void(long long, int)>& body,
                   long long chunk = 1);

 private:
  void workerLoop(int worker);
  void runChunks(int worker);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  // The current loop, written under mutex_. A worker joins a loop under mutex_ (active_ + 1) only
  // while it is open; the caller closes it when it runs out of chunks and then waits only for the
  // workers that joined, never for one that is still waking up.
  const std::function<void(long long, int)>* body_ = nullptr;
  long long count_ = 0;
  long long chunk_ = 1;
  bool open_ = false;
  bool stop_ = false;
  std::atomic<unsigned long long> generation_{0};  // bumped under mutex_; spun on without it
  std::atomic<int> active_{0};                     // changed under mutex_; spun on without it
  std::exception_ptr error_;                       // first exception of the current loop
  // Every chunk's fetch_add writes this line: on a line of its own, so that it does not evict the
  // fields above from the other core at each chunk.
  alignas(128) std::atomic<long long> next_{0};
};

int resolveThreadCount(int requested);

/// pool->parallelFor(count, body, chunk), or, without a pool, every index in order on the calling
/// thread as worker 0: for functions whose pool is optional.
void parallelForOrInline(ThreadPool* pool, long long count,
                         const std::function<void(long long, int)>& body, long long chunk = 1);

}  // namespace multimodal_nvs
