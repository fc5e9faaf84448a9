#pragma once
// The main() of the package's Google Benchmark binaries: the same allocator setting as the
// standalone nodes and the tools (retainFreedMemory), so a benchmark times the computation as the
// node runs it. Without it glibc unmaps each freed frame-sized buffer and the next iteration
// page-faults it in again (~30 us per 4 KiB page on this project's VMs); README says what a nodelet
// in a shared manager, which cannot make that process-wide choice, pays for it.
#include <benchmark/benchmark.h>

#include "multimodal_nvs/core/common/retain_freed_memory.hpp"

namespace multimodal_nvs {

inline int runBenchmarks(int argc, char** argv) {
  retainFreedMemory();  // before the benchmark library or a pool starts a thread
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace multimodal_nvs
