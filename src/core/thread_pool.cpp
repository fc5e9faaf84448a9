#include "multimodal_nvs/core/thread_pool.hpp"

#include <algorithm>

namespace multimodal_nvs {

int resolveThreadCount(int requested) {
  if (requested > 0) return requested;
  return std::max(1u, std::thread::hardware_concurrency());
}

ThreadPool::ThreadPool(int threads) {
  const int total = resolveThreadCount(threads);
  for (int w = 1; w < total; ++w) workers_.emplace_back([this, w] { workerLoop(w); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void ThreadPool::runChunks(int worker) {
  for (;;) {
    const long long begin = next_.fetch_add(chunk_);
    if (begin >= count_) return;
    const long long end = std::min(count_, begin + chunk_);
    for (long long i = begin; i < end; ++i) (*body_)(i, worker);
  }
}

void ThreadPool::workerLoop(int worker) {
  unsigned long long seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    runChunks(worker);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
    }
    done_.notify_one();
  }
}

void ThreadPool::parallelFor(long long count, const std::function<void(long long, int)>& body,
                             long long chunk) {
  if (count <= 0) return;
  if (workers_.empty() || count <= chunk) {
    for (long long i = 0; i < count; ++i) body(i, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    body_ = &body;
    count_ = count;
    chunk_ = std::max(1LL, chunk);
    next_ = 0;
    busy_ = static_cast<int>(workers_.size());
    ++generation_;
  }
  wake_.notify_all();
  runChunks(0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [&] { return busy_ == 0; });
  body_ = nullptr;
}

}  // namespace multimodal_nvs
