#pragma once
// A burst whose per-frame output work (encoding, metrics, export) overlaps with rendering.
#include <functional>

#include "multimodal_nvs/core/render/render_burst.hpp"

namespace multimodal_nvs {

/// What an export does with each rendered frame, in two stages.
struct BurstFrameStages {
  /// Runs on a worker thread, any number of frames at once and in any order: work that depends
  /// on this frame only (PNG encoding, the preview fill, metrics). `worker` is in [0, workers).
  /// May modify the frame; the ordered stage sees the result.
  std::function<void(int index, RenderedFrame& frame, int worker)> parallel;
  /// Runs once per frame after its parallel stage, strictly in trajectory order and one frame at
  /// a time (appending to a stream: the GEN3C arrays, a video). May be empty.
  std::function<void(int index, RenderedFrame& frame)> ordered;
};

struct BurstPipelineOptions {
  BurstOptions burst;
  /// Worker threads for the parallel stage (<= 0: all cores).
  int workers = 0;
  /// Rendered frames waiting for or inside their stages at most (<= 0: two chunks' worth): bounds
  /// memory (a gen3c frame at 704x1280 holds ~18 MB) while the workers stay busy.
  int max_pending_frames = 0;
};

/// renderBurstChunks whose chunks are handed, frame by frame, to a pool of `options.workers`
/// threads running `stages.parallel`, and then in order to `stages.ordered`; the next chunk is
/// rendered meanwhile. Outputs do not depend on the thread counts: each frame is rendered as by
/// renderBurstChunks and the ordered stage sees frames in trajectory order. The first exception
/// of a stage stops the burst (frames not yet started are skipped) and is rethrown here once
/// every worker has stopped; stats.render_ms counts the splatter only.
BurstStats renderBurstPipelined(PointSplatter& splatter, const ColoredCloud& cloud,
                                const Trajectory& trajectory, const SplatParams& params,
                                const BurstFrameStages& stages,
                                const BurstPipelineOptions& options = {});

}  // namespace multimodal_nvs
