#include "multimodal_nvs/core/render/gen3c_export.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
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

namespace {

int createFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw InputError(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  }
  return fd;
}

void writeFully(int fd, const std::string& path, const char* data, std::size_t bytes,
                std::size_t offset) {
  while (bytes > 0) {
    const ssize_t n = ::pwrite(fd, data, bytes, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      throw InputError(path + ": write failed (" +
                       (n < 0 ? std::string(std::strerror(errno)) : "no space?") + ")");
    }
    data += n;
    bytes -= static_cast<std::size_t>(n);
    offset += static_cast<std::size_t>(n);
  }
}

/// Rows per block: conversion and write go block by block so that the kernel's copy into the page
/// cache reads a buffer still in the core's cache. Whole 3.6 MB planes ran the copy at DRAM speed
/// while the other core rendered: writing 1.7 GB took about twice as long as in 512 KB blocks
/// (measured with a second thread streaming memory, as the export's splatter does).
int rowsPerBlock(int width) {
  constexpr std::size_t kBlockBytes = 512 * 1024;
  return std::max(
      1, static_cast<int>(kBlockBytes / (static_cast<std::size_t>(width) * sizeof(float))));
}

}  // namespace

Gen3cExportWriter::Gen3cExportWriter(const std::string& directory, int num_frames, ImageSize size)
    : num_frames_(num_frames), size_(size) {
  if (num_frames < 1 || size.height <= 0 || size.width <= 0) {
    throw InputError("GEN3C export needs at least one frame of positive size");
  }
  makeDirectories(directory);
  images_path_ = directory + "/rendered_warp_images.npy";
  masks_path_ = directory + "/rendered_warp_masks.npy";
  images_fd_ = createFile(images_path_);
  try {
    masks_fd_ = createFile(masks_path_);
  } catch (...) {
    ::close(images_fd_);
    throw;
  }
  const std::string image_header = io::npyHeader("<f4", gen3cImagesShape(num_frames, size));
  const std::string mask_header = io::npyHeader("<f4", gen3cMasksShape(num_frames, size));
  images_header_ = image_header.size();
  masks_header_ = mask_header.size();
  try {
    writeFully(images_fd_, images_path_, image_header.data(), image_header.size(), 0);
    writeFully(masks_fd_, masks_path_, mask_header.data(), mask_header.size(), 0);
  } catch (...) {
    ::close(images_fd_);
    ::close(masks_fd_);
    throw;
  }
  written_.assign(static_cast<std::size_t>(num_frames), false);
}

Gen3cExportWriter::~Gen3cExportWriter() {
  if (images_fd_ >= 0) ::close(images_fd_);
  if (masks_fd_ >= 0) ::close(masks_fd_);
}

std::vector<float> Gen3cExportWriter::takeBuffer() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!buffers_.empty()) {
      std::vector<float> buffer = std::move(buffers_.back());
      buffers_.pop_back();
      return buffer;
    }
  }
  return std::vector<float>(static_cast<std::size_t>(rowsPerBlock(size_.width)) *
                            static_cast<std::size_t>(size_.width));
}

void Gen3cExportWriter::returnBuffer(std::vector<float>&& buffer) {
  std::lock_guard<std::mutex> lock(mutex_);
  buffers_.push_back(std::move(buffer));
}

void Gen3cExportWriter::write(int index, const RenderedFrame& frame) {
  if (index < 0 || index >= num_frames_) {
    throw InputError(images_path_ + ": frame " + std::to_string(index) + " is not among the " +
                     "declared " + std::to_string(num_frames_) + " frames");
  }
  const bool has_signed = !frame.signed_bgr.empty();
  if (frame.mask.type() != CV_8UC1 || frame.mask.rows != size_.height ||
      frame.mask.cols != size_.width || frame.bgr.type() != CV_8UC3 ||
      frame.bgr.size() != frame.mask.size() ||
      (has_signed &&
       (frame.signed_bgr.type() != CV_32FC3 || frame.signed_bgr.size() != frame.mask.size()))) {
    throw InputError(images_path_ + ": frame " + std::to_string(index) + " is not " +
                     std::to_string(size_.height) + "x" + std::to_string(size_.width) +
                     " BGR8 + mask");
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) throw InputError(images_path_ + ": frame written after finish()");
    if (written_[static_cast<std::size_t>(index)]) {
      throw InputError(images_path_ + ": frame " + std::to_string(index) + " written twice");
    }
    written_[static_cast<std::size_t>(index)] = true;
  }
  std::vector<float> block = takeBuffer();
  const std::size_t row_bytes = static_cast<std::size_t>(size_.width) * sizeof(float);
  const std::size_t plane_bytes = row_bytes * static_cast<std::size_t>(size_.height);
  const int block_rows = rowsPerBlock(size_.width);
  // (1, N, 1, 3, H, W): frame i's three planes follow the header at i * 3 planes.
  const std::size_t image_offset =
      images_header_ + static_cast<std::size_t>(index) * 3 * plane_bytes;
  const std::size_t mask_offset = masks_header_ + static_cast<std::size_t>(index) * plane_bytes;
  for (int first = 0; first < size_.height; first += block_rows) {
    const int last = std::min(size_.height, first + block_rows);
    const std::size_t block_offset = static_cast<std::size_t>(first) * row_bytes;
    const std::size_t block_bytes = static_cast<std::size_t>(last - first) * row_bytes;
    // RGB order: plane 0 is red, i.e. OpenCV channel 2.
    for (int p = 0; p < 3; ++p) {
      const int channel = 2 - p;
      float* out = block.data();
      for (int r = first; r < last; ++r) {
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
      writeFully(images_fd_, images_path_, reinterpret_cast<const char*>(block.data()), block_bytes,
                 image_offset + static_cast<std::size_t>(p) * plane_bytes + block_offset);
    }
    float* out = block.data();
    for (int r = first; r < last; ++r) {
      const std::uint8_t* m = frame.mask.ptr<std::uint8_t>(r);
      for (int c = 0; c < size_.width; ++c)
        *out++ = m[c] != 0 ? 1.0f : 0.0f;
    }
    writeFully(masks_fd_, masks_path_, reinterpret_cast<const char*>(block.data()), block_bytes,
               mask_offset + block_offset);
  }
  returnBuffer(std::move(block));
}

void Gen3cExportWriter::finish() {
  std::size_t count = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) return;
    finished_ = true;
    for (bool w : written_)
      count += w;
    buffers_.clear();
  }
  const int images_closed = ::close(images_fd_), masks_closed = ::close(masks_fd_);
  images_fd_ = masks_fd_ = -1;
  if (count != static_cast<std::size_t>(num_frames_)) {
    throw InputError(images_path_ + ": " + std::to_string(count) + " frames written but the " +
                     "header declares " + std::to_string(num_frames_));
  }
  if (images_closed != 0 || masks_closed != 0) {
    throw InputError(images_path_ + ": closing failed (" + std::strerror(errno) + ")");
  }
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
