#pragma once
// Vectors aligned for Eigen's widest packets, so vectorised maths gives the same bits everywhere.
#include <cstddef>
#include <new>
#include <vector>

namespace multimodal_nvs {

/// Allocates with C++17 aligned new, not Eigen::aligned_allocator. Why: this package is built for
/// the build machine's CPU (AVX-512: Eigen aligns to 64 bytes by hand, storing the original
/// pointer in front of the block), while Debian's PCL is built for baseline x86-64 (Eigen uses
/// plain malloc) and exports some of the same std::vector<T, Eigen::aligned_allocator<T>>
/// instantiations (e.g. _M_default_append for float). In a process that loads libpcl_common
/// first, the dynamic linker binds our calls to PCL's copy: the buffer came from malloc and our
/// inlined destructor freed it as a hand-aligned block (a crash). Our own allocator type is a type
/// no other library instantiates.
template <typename T, std::size_t kAlignment = 64>
struct AlignedAllocator {
  using value_type = T;
  template <typename U>
  struct rebind {
    using other = AlignedAllocator<U, kAlignment>;
  };
  AlignedAllocator() noexcept = default;
  template <typename U>
  AlignedAllocator(const AlignedAllocator<U, kAlignment>&) noexcept {}

  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{kAlignment}));
  }
  void deallocate(T* p, std::size_t) noexcept {
    ::operator delete (p, std::align_val_t{kAlignment});
  }

  template <typename U>
  bool operator==(const AlignedAllocator<U, kAlignment>&) const noexcept {
    return true;
  }
  template <typename U>
  bool operator!=(const AlignedAllocator<U, kAlignment>&) const noexcept {
    return false;
  }
};

/// A vector aligned for Eigen's widest packets (64 bytes, AVX-512). Eigen processes the unaligned
/// head of a Map with scalar code (scalar exp differs from its vectorised exp in the last bit), so
/// with plain std::vector (16-byte aligned) a result could depend on where the allocator put the
/// buffer -- that is, on which thread ran. Every buffer that Eigen exponentiates uses this type.
template <typename T>
using SimdVector = std::vector<T, AlignedAllocator<T>>;

}  // namespace multimodal_nvs
