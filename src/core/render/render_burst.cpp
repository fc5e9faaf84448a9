#include "multimodal_nvs/core/render/render_burst.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <utility>

#include "multimodal_nvs/core/common/elapsed.hpp"

namespace multimodal_nvs {

std::optional<DepthResize> parseDepthResize(const std::string& name) {
  if (name == "auto") return DepthResize::kAuto;
  if (name == "yes") return DepthResize::kYes;
  if (name == "no") return DepthResize::kNo;
  return std::nullopt;
}

std::string toString(DepthResize choice) {
  switch (choice) {
    case DepthResize::kAuto:
      return "auto";
    case DepthResize::kYes:
      return "yes";
    case DepthResize::kNo:
      return "no";
  }
  return "auto";
}

bool resizesDepthToRender(DepthResize choice, SplatMode mode) {
  return choice == DepthResize::kYes || (choice == DepthResize::kAuto && mode == SplatMode::kGen3c);
}

bool resizesDepthToRender(DepthResize choice, SplatMode mode, const ImageSize& grid,
                          const ImageSize& render) {
  // auto also needs a grid at least the render size (a coarser grid is not upsampled).
  return resizesDepthToRender(choice, mode) &&
         (choice != DepthResize::kAuto ||
          (grid.height >= render.height && grid.width >= render.width));
}

int BurstOptions::chunkFramesFor(int threads) const {
  return chunk_frames > 0 ? chunk_frames : 2 * std::max(1, threads);
}

BurstStats renderBurstChunks(PointSplatter& splatter, const ColoredCloud& cloud,
                             const Trajectory& trajectory, const SplatParams& params,
                             const BurstChunkSink& sink, const BurstOptions& options) {
  BurstStats stats;
  stats.frames = static_cast<int>(trajectory.cameras.size());
  const int chunk = options.chunkFramesFor(splatter.threads());
  std::vector<RenderedFrame> frames;
  for (int first = 0; first < stats.frames; first += chunk) {
    const auto start = std::chrono::steady_clock::now();
    splatter.render(cloud, trajectory, first, std::min(chunk, stats.frames - first), params,
                    frames);
    stats.render_ms += millisecondsSince(start);
    ++stats.chunks;
    sink(first, frames);
  }
  return stats;
}

BurstStats renderBurst(PointSplatter& splatter, const ColoredCloud& cloud,
                       const Trajectory& trajectory, const SplatParams& params,
                       const BurstFrameSink& sink, const BurstOptions& options) {
  return renderBurstChunks(
      splatter, cloud, trajectory, params,
      [&sink](int first, const std::vector<RenderedFrame>& frames) {
        for (std::size_t i = 0; i < frames.size(); ++i)
          sink(first + static_cast<int>(i), frames[i]);
      },
      options);
}

std::optional<std::string> gen3cSizeWarning(int num_frames, ImageSize size) {
  if (num_frames == kGen3cFrames && size.height == kGen3cHeight && size.width == kGen3cWidth) {
    return std::nullopt;
  }
  return "GEN3C expects " + std::to_string(kGen3cFrames) + " frames at " +
         std::to_string(kGen3cHeight) + "x" + std::to_string(kGen3cWidth) +
         "; the export uses the requested " + std::to_string(num_frames) + " frames at " +
         std::to_string(size.height) + "x" + std::to_string(size.width);
}

Gen3cBurstExport::Gen3cBurstExport(std::string folder, const cv::Mat& input_image_bgr,
                                   int num_frames, ImageSize size, Gen3cFolderWrite write)
    : folder_(std::move(folder)) {
  writing_ = write == Gen3cFolderWrite::kRenameWhenComplete ? folder_ + ".partial" : folder_;
  if (write == Gen3cFolderWrite::kRenameWhenComplete) std::filesystem::remove_all(writing_);
  writer_ = std::make_unique<Gen3cExportWriter>(writing_, num_frames, size);
  writeGen3cCompanions(writing_, input_image_bgr, num_frames, size);
}

void Gen3cBurstExport::finish() {
  writer_->finish();
  writer_.reset();
  if (writing_ != folder_) {
    std::filesystem::remove_all(folder_);
    std::filesystem::rename(writing_, folder_);
  }
}

}  // namespace multimodal_nvs
