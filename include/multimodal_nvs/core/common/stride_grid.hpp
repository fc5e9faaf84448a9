#pragma once
// The output raster of depth completion: every stride-th pixel of the full image.
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
};

}  // namespace multimodal_nvs
