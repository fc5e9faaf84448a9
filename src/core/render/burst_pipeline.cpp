#include "multimodal_nvs/core/render/burst_pipeline.hpp"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {
namespace {

/// The frames between the splatter and the ordered stage. Workers take frames in render order;
/// a finished frame waits in `done` until every earlier frame has passed the ordered stage, and
/// the worker that finishes the next frame in order runs the ordered stage (one at a time).
class FramePipeline {
 public:
  FramePipeline(const BurstFrameStages& stages, int workers, int max_pending, int total)
      : stages_(stages), max_pending_(max_pending), done_(static_cast<std::size_t>(total)) {
    for (int w = 0; w < workers; ++w)
      threads_.emplace_back([this, w] { work(w); });
  }

  ~FramePipeline() { stop(); }

  /// Drops the frames no worker has taken and joins the workers.
  void cancel() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.clear();
    }
    stop();
  }

  /// Blocks while max_pending frames are in flight; false once a stage has failed.
  bool push(int index, RenderedFrame&& frame) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return failed() || pushed_ - committed_ < max_pending_; });
    if (failed()) return false;
    queue_.emplace_back(index, std::move(frame));
    ++pushed_;
    changed_.notify_all();
    return true;
  }

  /// Waits for every pushed frame (or the first failure), joins the workers and rethrows.
  void finish() {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return failed() || committed_ == pushed_; });
    }
    stop();
    if (error_) std::rethrow_exception(error_);
  }

 private:
  bool failed() const { return error_ != nullptr; }

  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    changed_.notify_all();
    for (std::thread& t : threads_)
      if (t.joinable()) t.join();
  }

  void fail(std::exception_ptr error) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::move(error);
    queue_.clear();
    changed_.notify_all();
  }

  void work(int worker) {
    for (;;) {
      std::pair<int, RenderedFrame> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait(lock, [&] { return stopping_ || failed() || !queue_.empty(); });
        if (failed() || queue_.empty()) return;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      try {
        if (stages_.parallel) stages_.parallel(job.first, job.second, worker);
        commitInOrder(job.first, std::move(job.second));
      } catch (...) {
        fail(std::current_exception());
        return;
      }
    }
  }

  /// Stores the frame and, unless another worker is at it, runs the ordered stage for every
  /// frame that is next in order.
  void commitInOrder(int index, RenderedFrame&& frame) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_[static_cast<std::size_t>(index)] = std::move(frame);
    ready_.push_back(index);
    if (committing_) return;
    committing_ = true;
    for (;;) {
      const auto next = std::find(ready_.begin(), ready_.end(), committed_);
      if (next == ready_.end() || failed()) break;
      ready_.erase(next);
      RenderedFrame current = std::move(done_[static_cast<std::size_t>(committed_)]);
      const int current_index = committed_;
      lock.unlock();
      try {
        if (stages_.ordered) stages_.ordered(current_index, current);
      } catch (...) {
        lock.lock();
        committing_ = false;
        throw;
      }
      current = RenderedFrame{};  // free the frame's buffers outside the lock
      lock.lock();
      ++committed_;
      changed_.notify_all();
    }
    committing_ = false;
  }

  const BurstFrameStages& stages_;
  const int max_pending_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::pair<int, RenderedFrame>> queue_;
  std::vector<RenderedFrame> done_;  ///< finished frames waiting for the ordered stage
  std::vector<int> ready_;           ///< their indices
  int pushed_ = 0, committed_ = 0;
  bool committing_ = false, stopping_ = false;
  std::exception_ptr error_;
  std::vector<std::thread> threads_;
};

}  // namespace

BurstStats renderBurstPipelined(PointSplatter& splatter, const ColoredCloud& cloud,
                                const Trajectory& trajectory, const SplatParams& params,
                                const BurstFrameStages& stages,
                                const BurstPipelineOptions& options) {
  const int workers = resolveThreadCount(options.workers);
  const int chunk = options.burst.chunkFramesFor(splatter.threads());
  const int max_pending = options.max_pending_frames > 0 ? options.max_pending_frames : 2 * chunk;
  FramePipeline pipeline(stages, workers, max_pending, static_cast<int>(trajectory.cameras.size()));
  BurstStats stats;
  try {
    stats = renderBurstChunks(
        splatter, cloud, trajectory, params,
        [&](int first, std::vector<RenderedFrame>& frames) {
          // Moved, not copied: the splatter allocates the next chunk's buffers afresh.
          for (std::size_t i = 0; i < frames.size(); ++i)
            if (!pipeline.push(first + static_cast<int>(i), std::move(frames[i]))) return;
        },
        options.burst);
  } catch (...) {
    pipeline.cancel();  // the splatter's error wins over a stage's
    throw;
  }
  pipeline.finish();
  return stats;
}

}  // namespace multimodal_nvs
