#pragma once
// The folder of arrays GEN3C's diffusion stage loads, written frame by frame.
#include <cstddef>
#include <fstream>
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

/// Streams conditioning frames into the two float32 .npy files of the GEN3C folder, one frame at
/// a time (the full arrays are 1.3 GB and 0.4 GB), RGB planes in [-1, 1] with holes exactly -1 and
/// masks exactly 0 or 1. Frames must be appended in order; finish() checks the count and closes.
class Gen3cExportWriter {
 public:
  /// Creates `directory` if needed and opens rendered_warp_images.npy and rendered_warp_masks.npy.
  Gen3cExportWriter(const std::string& directory, int num_frames, ImageSize size);
  ~Gen3cExportWriter();
  Gen3cExportWriter(const Gen3cExportWriter&) = delete;
  Gen3cExportWriter& operator=(const Gen3cExportWriter&) = delete;

  /// Uses frame.signed_bgr when present (gen3c mode, unquantised), else bgr / 127.5 - 1.
  void append(const RenderedFrame& frame);
  /// Throws InputError unless exactly num_frames frames were appended and both files were written.
  void finish();

  const std::string& imagesPath() const { return images_path_; }
  const std::string& masksPath() const { return masks_path_; }

 private:
  std::string images_path_, masks_path_;
  std::ofstream images_, masks_;
  int num_frames_;
  ImageSize size_;
  int written_ = 0;
  std::vector<float> plane_;
  bool finished_ = false;
};

/// input_image.png (the reference image at the render size) and README.md with the Python one-liner
/// that turns the arrays into the torch tensors the diffusion stage loads.
void writeGen3cCompanions(const std::string& directory, const cv::Mat& input_image_bgr,
                          int num_frames, ImageSize size);

/// Creates a directory and its parents; throws InputError naming it on failure.
void makeDirectories(const std::string& directory);

}  // namespace multimodal_nvs
