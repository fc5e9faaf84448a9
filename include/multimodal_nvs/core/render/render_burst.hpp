#pragma once
// The one way to render a whole trajectory: frames in chunks, handed in order to a sink; with the
// depth resize rule and the GEN3C export every caller of a burst shares.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/gen3c_export.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"

namespace multimodal_nvs {

// ---- Depth resize rule
// ----------------------------------------------------------------------------

/// Whether the depth map (and image) are resampled to the render size before they are lifted.
enum class DepthResize {
  kAuto,  ///< for gen3c only: GEN3C's own preparation resamples 1216x1936 to 704x1280
  kYes,
  kNo,
};

/// "auto" | "yes" | "no"; nullopt for anything else (the caller names the option in its error).
std::optional<DepthResize> parseDepthResize(const std::string& name);
std::string toString(DepthResize choice);

/// The rule for a depth map of any size (render_conditioning's --resize-depth): yes, no, or for
/// auto whether `mode` is gen3c.
bool resizesDepthToRender(DepthResize choice, SplatMode mode);

/// The rule once the depth grid is known (the renderer nodelet's keyframes): auto resamples for
/// gen3c only when `grid` is at least `render` on both axes, as GEN3C's own input is. A smaller
/// grid (the depth nodelet's stride 2 gives 608x968) is lifted one point per grid pixel instead:
/// its nearest-index scatter would leave empty rows and columns, which the depth-edge filter
/// (zero-padded 5x5 window) reads as edges, removing nearly every point. yes and no are taken as
/// they are.
bool resizesDepthToRender(DepthResize choice, SplatMode mode, const ImageSize& grid,
                          const ImageSize& render);

// ---- Burst
// ----------------------------------------------------------------------------------------

struct BurstOptions {
  /// Frames per PointSplatter::render call. 0: two per worker thread, which keeps memory bounded
  /// (a gen3c frame at 704x1280 holds ~20 MB) while every core stays busy.
  int chunk_frames = 0;

  /// The chunk size used with a splatter of `threads` workers.
  int chunkFramesFor(int threads) const;
};

/// One chunk of a burst: frames[i] is view first + i of the trajectory. The frames are
/// overwritten by the next chunk; a sink that keeps a frame moves it out (a shallow cv::Mat copy
/// would be overwritten: cv::Mat::create reuses a buffer of the right size whatever its reference
/// count), and the splatter allocates that frame's buffers afresh.
using BurstChunkSink = std::function<void(int first, std::vector<RenderedFrame>& frames)>;
/// One frame of a burst: view `index` of the trajectory, handed over in trajectory order.
using BurstFrameSink = std::function<void(int index, const RenderedFrame& frame)>;

struct BurstStats {
  int frames = 0;
  int chunks = 0;
  double render_ms = 0.0;  ///< time inside the splatter only (the sink's time excluded)
};

/// Renders every view of `trajectory` from `cloud`, a chunk at a time, and hands each chunk to
/// `sink` before the next is rendered. The frames do not depend on the chunk size or the thread
/// count (GEN3C's soft z-buffer batches are fixed by params.gen3c_batch and trajectory indices).
/// Throws InputError as PointSplatter::render does; exceptions of the sink propagate.
BurstStats renderBurstChunks(PointSplatter& splatter, const ColoredCloud& cloud,
                             const Trajectory& trajectory, const SplatParams& params,
                             const BurstChunkSink& sink, const BurstOptions& options = {});

/// renderBurstChunks with the frames handed over one at a time.
BurstStats renderBurst(PointSplatter& splatter, const ColoredCloud& cloud,
                       const Trajectory& trajectory, const SplatParams& params,
                       const BurstFrameSink& sink, const BurstOptions& options = {});

// ---- GEN3C export of a burst
// ----------------------------------------------------------------------

/// The warning for an export GEN3C's diffusion stage will not take as it is (it expects 121 frames
/// at 704x1280); nullopt when `num_frames` and `size` are GEN3C's.
std::optional<std::string> gen3cSizeWarning(int num_frames, ImageSize size);

enum class Gen3cFolderWrite {
  kInPlace,  ///< straight into the folder (a tool's output directory)
  /// Under FOLDER.partial, renamed to FOLDER by finish(): a reader watching the export directory
  /// never sees half a folder. A previous FOLDER or FOLDER.partial is replaced.
  kRenameWhenComplete,
};

/// A burst's GEN3C folder: the arrays streamed frame by frame (Gen3cExportWriter) and the
/// companions (writeGen3cCompanions), written as the constructor's `write` says. Throws
/// InputError (and std::filesystem::filesystem_error when renaming) on failure; an unfinished
/// export leaves its files where they were written.
class Gen3cBurstExport {
 public:
  Gen3cBurstExport(std::string folder, const cv::Mat& input_image_bgr, int num_frames,
                   ImageSize size, Gen3cFolderWrite write);

  void append(const RenderedFrame& frame) { writer_->append(frame); }
  /// Frame `index`, from any thread, in any order (Gen3cExportWriter::write).
  void write(int index, const RenderedFrame& frame) { writer_->write(index, frame); }
  /// Checks the frame count, closes the arrays and, for kRenameWhenComplete, renames the folder.
  void finish();

  /// Where the folder is once finished.
  const std::string& folder() const { return folder_; }

 private:
  std::string folder_;
  std::string writing_;  ///< where the files are written until finish()
  std::unique_ptr<Gen3cExportWriter> writer_;
};

}  // namespace multimodal_nvs
