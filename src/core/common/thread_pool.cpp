#include "multimodal_nvs/core/common/thread_pool.hpp"

#include <algorithm>
#include <chrono>

namespace multimodal_nvs {

void parallelForOrInline(ThreadPool* pool, long long count,
                         const std::function<void(long long, int)>& body, long long chunk) {
  if (pool != nullptr) {
    pool->parallelFor(count, body, chunk);
    return;
  }
  for (long long i = 0; i < count; ++i)
    body(i, 0);
}

int resolveThreadCount(int requested) {
  if (requested > 0) return requested;
  return std::max(1u, std::thread::hardware_concurrency());
}

ThreadPool::ThreadPool(int threads) {
  const int total = resolveThreadCount(threads);
  for (int w = 1; w < total; ++w)
    workers_.emplace_back([this, w] { workerLoop(w); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  for (auto& t : workers_)
    t.join();
}

namespace {

/// Spins for up to ~50 us until ready() holds; false if it did not. Waking a thread that sleeps on
/// a condition variable took ~65 us (median) on the 2-core virtual machine of the measured
/// performance, once per loop, and a frame runs tens of loops with short serial steps between
/// them; a worker that spins that long after each loop is there when the next one starts. It
/// yields while it spins, so a thread outside the pool that needs the core gets it.
template <class Ready>
bool spinFor(Ready&& ready) {
  constexpr auto kSpin = std::chrono::microseconds(50);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0;; ++i) {
    if (ready()) return true;
    if ((i & 15) == 15) {
      if (std::chrono::steady_clock::now() - start > kSpin) return false;
      std::this_thread::yield();
    }
  }
}

}  // namespace

void ThreadPool::runChunks(int worker) {
  // The loop's description does not change while this thread is in it (joined under mutex_).
  const long long count = count_, chunk = chunk_;
  const std::function<void(long long, int)>& body = *body_;
  try {
    for (;;) {
      const long long begin = next_.fetch_add(chunk, std::memory_order_relaxed);
      if (begin >= count) return;
      const long long end = std::min(count, begin + chunk);
      for (long long i = begin; i < end; ++i)
        body(i, worker);
    }
  } catch (...) {
    // An exception escaping a worker thread would call std::terminate (a std::bad_alloc on a huge
    // input would kill the whole nodelet manager): keep the first one, hand out no further chunks,
    // and let parallelFor rethrow it on the calling thread once every worker has stopped.
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::current_exception();
    next_.store(count);
  }
}

void ThreadPool::workerLoop(int worker) {
  unsigned long long seen = 0;
  for (;;) {
    const auto news = [&] { return generation_.load(std::memory_order_acquire) != seen; };
    if (!spinFor(news)) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, news);
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
      seen = generation_.load(std::memory_order_relaxed);
      if (!open_) continue;  // the loop ended without this worker
      active_.fetch_add(1, std::memory_order_relaxed);
    }
    runChunks(worker);
    std::lock_guard<std::mutex> lock(mutex_);
    if (active_.fetch_sub(1, std::memory_order_release) == 1) done_.notify_one();
  }
}

void ThreadPool::parallelFor(long long count, const std::function<void(long long, int)>& body,
                             long long chunk) {
  if (count <= 0) return;
  if (workers_.empty() || count <= chunk) {
    for (long long i = 0; i < count; ++i)
      body(i, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    body_ = &body;
    count_ = count;
    chunk_ = std::max(1LL, chunk);
    next_.store(0, std::memory_order_relaxed);
    open_ = true;
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();  // no system call when every worker is spinning
  runChunks(0);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = false;  // no worker joins any more; wait only for those that did
  }
  if (!spinFor([&] { return active_.load(std::memory_order_acquire) == 0; })) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return active_.load(std::memory_order_relaxed) == 0; });
  }
  std::unique_lock<std::mutex> lock(mutex_);
  body_ = nullptr;
  if (error_) {
    std::exception_ptr error = nullptr;
    std::swap(error, error_);
    lock.unlock();
    std::rethrow_exception(error);
  }
}

}  // namespace multimodal_nvs
