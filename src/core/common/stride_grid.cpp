#include "multimodal_nvs/core/common/stride_grid.hpp"

namespace multimodal_nvs {

PinholeIntrinsics StrideGrid::gridIntrinsics(const PinholeIntrinsics& image_k) const {
  return {image_k.fx / stride, image_k.fy / stride, image_k.cx / stride, image_k.cy / stride,
          image_k.distortion};
}

PinholeIntrinsics StrideGrid::imageIntrinsics(const PinholeIntrinsics& grid_k) const {
  return {grid_k.fx * stride, grid_k.fy * stride, grid_k.cx * stride, grid_k.cy * stride,
          grid_k.distortion};
}

std::optional<StrideGrid> strideGridOfSize(const ImageSize& image, const ImageSize& raster) {
  for (int s = 1; s <= 64; ++s) {
    const StrideGrid grid{image, s};
    if (grid.rows() == raster.height && grid.cols() == raster.width) return grid;
  }
  return std::nullopt;
}

}  // namespace multimodal_nvs
