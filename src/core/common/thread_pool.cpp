#include "multimodal_nvs/core/common/thread_pool.hpp"

#include <algorithm>

namespace multimodal_nvs {

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
  }
  wake_.notify_all();
  for (auto& t : workers_)
    t.join();
}

void ThreadPool::runChunks(int worker) {
  try {
    for (;;) {
      const long long begin = next_.fetch_add(chunk_);
      if (begin >= count_) return;
      const long long end = std::min(count_, begin + chunk_);
      for (long long i = begin; i < end; ++i)
        (*body_)(i, worker);
    }
  } catch (...) {
    // An exception escaping a worker thread would call std::terminate (a std::bad_alloc on a huge
    // input would kill the whole nodelet manager): keep the first one, hand out no further chunks,
    // and let parallelFor rethrow it on the calling thread once every worker has stopped.
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::current_exception();
    next_.store(count_);
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
    for (long long i = 0; i < count; ++i)
      body(i, 0);
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
  if (error_) {
    std::exception_ptr error = nullptr;
    std::swap(error, error_);
    lock.unlock();
    std::rethrow_exception(error);
  }
}

}  // namespace multimodal_nvs
