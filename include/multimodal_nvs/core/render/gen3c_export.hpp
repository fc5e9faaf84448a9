#pragma once
// The folder of arrays GEN3C's diffusion stage loads, written frame by frame.
#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"

namespace multimodal_nvs {

/// What GEN3C's diffusion stage loads (GEN3C's published renderer): 121 frames at 704 x 1280.
constexpr int kGen3cFrames = 121;
constexpr int kGen3cHeight = 704;
constexpr int kGen3cWidth = 1280;

/// (1, N, 1, 3, H, W): rendered_warp_images. (1, N, 1, 1, H, W): rendered_warp_masks.
std::vector<std::size_t> gen3cImagesShape(int num_frames, ImageSize size);
std::vector<std::size_t> gen3cMasksShape(int num_frames, ImageSize size);

/// Writes conditioning frames into the two float32 .npy files of the GEN3C folder, one frame at a
/// time (the full arrays are 1.3 GB and 0.4 GB), RGB planes in [-1, 1] with holes exactly -1 and
/// masks exactly 0 or 1. Each frame has a fixed place in both files, so `write` may be called from
/// several threads at once and in any order (each index once): an export's workers write the 1.7 GB
/// beside each other instead of one after another. finish() checks that every frame was written.
class Gen3cExportWriter {
 public:
  /// Creates `directory` if needed, creates rendered_warp_images.npy and rendered_warp_masks.npy
  /// and writes their headers.
  Gen3cExportWriter(const std::string& directory, int num_frames, ImageSize size);
  ~Gen3cExportWriter();
  Gen3cExportWriter(const Gen3cExportWriter&) = delete;
  Gen3cExportWriter& operator=(const Gen3cExportWriter&) = delete;

  /// Frame `index` (0-based). Uses frame.signed_bgr when present (gen3c mode, unquantised), else
  /// bgr / 127.5 - 1. Thread-safe; throws InputError on a bad index, a repeated index, a frame of
  /// the wrong size or a failed write.
  void write(int index, const RenderedFrame& frame);
  /// The next frame in order: write(number of frames appended so far, frame). Not to be mixed with
  /// write() from other threads.
  void append(const RenderedFrame& frame) { write(appended_++, frame); }
  /// Throws InputError unless every frame was written and both files closed cleanly.
  void finish();

  const std::string& imagesPath() const { return images_path_; }
  const std::string& masksPath() const { return masks_path_; }

 private:
  std::vector<float> takeBuffer();
  void returnBuffer(std::vector<float>&& buffer);

  std::string images_path_, masks_path_;
  int images_fd_ = -1, masks_fd_ = -1;
  std::size_t images_header_ = 0, masks_header_ = 0;
  int num_frames_;
  ImageSize size_;
  int appended_ = 0;
  std::mutex mutex_;  ///< guards written_, buffers_ and finished_
  std::vector<bool> written_;
  /// One block of rows per thread writing at the moment, kept: a fresh buffer per frame would be
  /// faulted in page by page every time.
  std::vector<std::vector<float>> buffers_;
  bool finished_ = false;
};

/// input_image.png (the reference image at the render size) and README.md with the Python one-liner
/// that turns the arrays into the torch tensors the diffusion stage loads.
void writeGen3cCompanions(const std::string& directory, const cv::Mat& input_image_bgr,
                          int num_frames, ImageSize size);

/// Creates a directory and its parents; throws InputError naming it on failure.
void makeDirectories(const std::string& directory);

}  // namespace multimodal_nvs
