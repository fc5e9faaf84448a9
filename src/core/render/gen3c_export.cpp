#include "multimodal_nvs/core/render/gen3c_export.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/npy.hpp"

namespace multimodal_nvs {

std::vector<std::size_t> gen3cImagesShape(int num_frames, ImageSize size) {
  return {1, static_cast<std::size_t>(num_frames),  1,
          3, static_cast<std::size_t>(size.height), static_cast<std::size_t>(size.width)};
}

std::vector<std::size_t> gen3cMasksShape(int num_frames, ImageSize size) {
  return {1, static_cast<std::size_t>(num_frames),  1,
          1, static_cast<std::size_t>(size.height), static_cast<std::size_t>(size.width)};
}

void makeDirectories(const std::string& directory) {
  std::string path;
  std::size_t start = 0;
  while (start <= directory.size()) {
    const std::size_t slash = directory.find('/', start);
    path = directory.substr(0, slash == std::string::npos ? directory.size() : slash);
    if (!path.empty() && ::mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) {
      throw InputError(path + ": cannot create directory (" + std::strerror(errno) + ")");
    }
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  struct stat st;
  if (::stat(directory.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
    throw InputError(directory + ": not a directory");
  }
}

Gen3cExportWriter::Gen3cExportWriter(const std::string& directory, int num_frames, ImageSize size)
    : num_frames_(num_frames), size_(size) {
  if (num_frames < 1 || size.height <= 0 || size.width <= 0) {
    throw InputError("GEN3C export needs at least one frame of positive size");
  }
  makeDirectories(directory);
  images_path_ = directory + "/rendered_warp_images.npy";
  masks_path_ = directory + "/rendered_warp_masks.npy";
  images_.open(images_path_, std::ios::binary | std::ios::trunc);
  if (!images_) throw InputError(images_path_ + ": cannot open for writing");
  masks_.open(masks_path_, std::ios::binary | std::ios::trunc);
  if (!masks_) throw InputError(masks_path_ + ": cannot open for writing");
  const std::string image_header = io::npyHeader("<f4", gen3cImagesShape(num_frames, size));
  const std::string mask_header = io::npyHeader("<f4", gen3cMasksShape(num_frames, size));
  images_.write(image_header.data(), static_cast<std::streamsize>(image_header.size()));
  masks_.write(mask_header.data(), static_cast<std::streamsize>(mask_header.size()));
  plane_.resize(static_cast<std::size_t>(size.pixels()));
}

Gen3cExportWriter::~Gen3cExportWriter() = default;

void Gen3cExportWriter::append(const RenderedFrame& frame) {
  if (finished_) throw InputError(images_path_ + ": frame appended after finish()");
  if (written_ >= num_frames_) {
    throw InputError(images_path_ + ": more than the declared " + std::to_string(num_frames_) +
                     " frames appended");
  }
  const bool has_signed = !frame.signed_bgr.empty();
  if (frame.mask.type() != CV_8UC1 || frame.mask.rows != size_.height ||
      frame.mask.cols != size_.width || frame.bgr.type() != CV_8UC3 ||
      frame.bgr.size() != frame.mask.size() ||
      (has_signed &&
       (frame.signed_bgr.type() != CV_32FC3 || frame.signed_bgr.size() != frame.mask.size()))) {
    throw InputError(images_path_ + ": frame " + std::to_string(written_) + " is not " +
                     std::to_string(size_.height) + "x" + std::to_string(size_.width) +
                     " BGR8 + mask");
  }
  const std::streamsize plane_bytes = static_cast<std::streamsize>(plane_.size() * sizeof(float));
  // RGB order: plane 0 is red, i.e. OpenCV channel 2.
  for (int plane = 0; plane < 3; ++plane) {
    const int channel = 2 - plane;
    float* out = plane_.data();
    for (int r = 0; r < size_.height; ++r) {
      const std::uint8_t* m = frame.mask.ptr<std::uint8_t>(r);
      if (has_signed) {
        const cv::Vec3f* s = frame.signed_bgr.ptr<cv::Vec3f>(r);
        for (int c = 0; c < size_.width; ++c)
          *out++ = m[c] != 0 ? s[c][channel] : -1.0f;
      } else {
        const cv::Vec3b* b = frame.bgr.ptr<cv::Vec3b>(r);
        for (int c = 0; c < size_.width; ++c) {
          *out++ = m[c] != 0 ? static_cast<float>(b[c][channel]) / 127.5f - 1.0f : -1.0f;
        }
      }
    }
    images_.write(reinterpret_cast<const char*>(plane_.data()), plane_bytes);
  }
  float* out = plane_.data();
  for (int r = 0; r < size_.height; ++r) {
    const std::uint8_t* m = frame.mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < size_.width; ++c)
      *out++ = m[c] != 0 ? 1.0f : 0.0f;
  }
  masks_.write(reinterpret_cast<const char*>(plane_.data()), plane_bytes);
  if (!images_ || !masks_) throw InputError(images_path_ + ": write failed (disk full?)");
  ++written_;
}

void Gen3cExportWriter::finish() {
  if (finished_) return;
  finished_ = true;
  images_.close();
  masks_.close();
  if (written_ != num_frames_) {
    throw InputError(images_path_ + ": " + std::to_string(written_) + " frames written but the " +
                     "header declares " + std::to_string(num_frames_));
  }
  if (images_.fail() || masks_.fail()) throw InputError(images_path_ + ": closing failed");
}

void writeGen3cCompanions(const std::string& directory, const cv::Mat& input_image_bgr,
                          int num_frames, ImageSize size) {
  makeDirectories(directory);
  cv::Mat resized;
  cv::resize(input_image_bgr, resized, cv::Size(size.width, size.height), 0, 0, cv::INTER_LINEAR);
  const std::string image_path = directory + "/input_image.png";
  if (!cv::imwrite(image_path, resized)) throw InputError(image_path + ": cannot write");
  const std::string readme_path = directory + "/README.md";
  std::ofstream readme(readme_path);
  if (!readme) throw InputError(readme_path + ": cannot write");
  const std::string n = std::to_string(num_frames), h = std::to_string(size.height),
                    w = std::to_string(size.width);
  readme << "# GEN3C conditioning (written by multimodal_nvs render_conditioning)\n\n"
         << "- `rendered_warp_images.npy`: float32, shape (1, " << n << ", 1, 3, " << h << ", " << w
         << "), RGB in [-1, 1], holes exactly -1. Frame 0 is the reference view.\n"
         << "- `rendered_warp_masks.npy`: float32, shape (1, " << n << ", 1, 1, " << h << ", " << w
         << "), 1 where a point was splatted, 0 in holes.\n"
         << "- `input_image.png`: the reference image at " << h << "x" << w << " (bilinear).\n\n"
         << "The tensors the diffusion stage loads:\n\n```python\n"
         << "import numpy as np, torch; rendered_warp_images, rendered_warp_masks = "
            "(torch.from_numpy(np.load(f)) for f in (\"rendered_warp_images.npy\", "
            "\"rendered_warp_masks.npy\"))\n"
         << "```\n";
  if (!readme) throw InputError(readme_path + ": write failed");
}

}  // namespace multimodal_nvs
