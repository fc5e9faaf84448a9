#pragma once
// One object per pool worker, each on cache lines of its own.
#include <cstddef>
#include <vector>

namespace multimodal_nvs {

/// Per-worker scratch for ThreadPool::parallelFor bodies (index it with the body's `worker`).
/// Workers' objects side by side in a plain std::vector share cache lines: a worker's push_back
/// writes its vector's end pointer, which evicts the line from the other core, which then stalls
/// on its own reads of the same line (false sharing). 128 bytes, not 64: adjacent-line prefetching
/// moves lines in pairs.
template <class T>
class PerWorker {
 public:
  explicit PerWorker(int workers, const T& initial = T()) : slots_(workers, Slot{initial}) {}
  T& operator[](int worker) { return slots_[worker].value; }
  const T& operator[](int worker) const { return slots_[worker].value; }
  int size() const { return static_cast<int>(slots_.size()); }

 private:
  struct alignas(128) Slot {
    T value;
  };
  std::vector<Slot> slots_;
};

}  // namespace multimodal_nvs
