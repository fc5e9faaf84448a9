#pragma once
// An engine with its own thread pool, kept between frames and built again only when the requested
// thread count changes (a node's engines: DepthCompleter, PointSplatter).
#include <memory>

namespace multimodal_nvs {

/// Holds one `Engine(threads)`, rebuilt when `forThreads` asks for another count. Not thread-safe:
/// used by one frame callback at a time.
template <class Engine>
class ThreadCountCached {
 public:
  Engine& forThreads(int threads) {
    if (!engine_ || threads != threads_) {
      engine_ = std::make_unique<Engine>(threads);
      threads_ = threads;
    }
    return *engine_;
  }
  /// The engine the last forThreads() built; null before the first call.
  Engine* current() { return engine_.get(); }

 private:
  std::unique_ptr<Engine> engine_;
  int threads_ = -1;
};

}  // namespace multimodal_nvs
