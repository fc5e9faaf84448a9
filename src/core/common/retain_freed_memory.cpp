#include "multimodal_nvs/core/common/retain_freed_memory.hpp"

#include <cstdlib>  // defines __GLIBC__ when the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace multimodal_nvs {

bool retainFreedMemory() {
#if defined(__GLIBC__)
  // 32 MB is the largest mmap threshold glibc accepts on 64-bit (half its heap size); setting it
  // also stops glibc from moving the threshold itself.
  constexpr int kMmapThreshold = 32 << 20;
  constexpr int kTrimThreshold = 512 << 20;
  // One arena: a thread's own arena lives in 64 MB heaps that glibc unmaps as soon as one is
  // empty, whatever the trim threshold, and frames are allocated by the splatter's threads and
  // freed by the writers'. The allocations here are few and large, so the shared lock is cheap.
  return mallopt(M_ARENA_MAX, 1) == 1 && mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 &&
         mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
#else
  return false;
#endif
}

}  // namespace multimodal_nvs
