#pragma once
// The output raster of depth completion: every stride-th pixel of the full image.
#include <optional>

#include "multimodal_nvs/core/common/camera.hpp"

namespace multimodal_nvs {

/// Output raster: pixel centres u = 0, s, 2s, ... and v = 0, s, 2s, ... of the full image (no
/// +0.5), shape ceil(H/s) x ceil(W/s); intrinsics are not rescaled.
struct StrideGrid {
  ImageSize image;
  int stride = 1;
  int rows() const { return (image.height + stride - 1) / stride; }
  int cols() const { return (image.width + stride - 1) / stride; }
  long long size() const { return static_cast<long long>(rows()) * cols(); }
  bool operator==(const StrideGrid& o) const { return image == o.image && stride == o.stride; }

  /// The grid as a camera of its own: the image's K / s (no half-pixel shift, as the grid starts
  /// at pixel 0).
  PinholeIntrinsics gridIntrinsics(const PinholeIntrinsics& image_k) const;
  /// The other way round: the image's K from the grid's, K s.
  PinholeIntrinsics imageIntrinsics(const PinholeIntrinsics& grid_k) const;
};

/// The grid of `image` whose raster is `raster` in size (ceil(H/s) x ceil(W/s)), for the smallest
/// stride 1..64 that gives it: how a depth map written on a stride grid (complete_depth --stride,
/// the depth nodelet's `stride`) is matched with its full image. nullopt when no stride does.
std::optional<StrideGrid> strideGridOfSize(const ImageSize& image, const ImageSize& raster);

}  // namespace multimodal_nvs
