#pragma once
// Kept pixels lifted into a coloured cloud, after GEN3C's depth preparation.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/camera.hpp"
#include "multimodal_nvs/core/common/stride_grid.hpp"

namespace multimodal_nvs {

/// Kept pixels lifted into the reference camera frame (x right, y down, z forward), one point per
/// pixel, stored as separate arrays so that the splatting loops stream through them.
struct ColoredCloud {
  std::vector<float> x, y, z;
  /// Colour of each point packed as B | G << 8 | R << 16 (OpenCV channel order).
  std::vector<std::uint32_t> bgr;
  /// The pixel grid the points were lifted from. The splatter compares its focal length with the
  /// target's to know how far apart neighbouring points land (the zbuffer footprint).
  PinholeIntrinsics intrinsics;
  ImageSize grid;

  std::size_t size() const { return z.size(); }
  /// Median of z (the orbit centre of the presets); 0 for an empty cloud.
  double medianDepth() const;
};

/// How the depth map is prepared before lifting. The defaults are GEN3C's own (GEN3C's published
/// renderer).
struct BackprojectionParams {
  /// Resample image (bilinear) and depth (nearest-index scatter) to `render_size` first, so there
  /// is one point per render pixel, as GEN3C does. Off: one point per depth pixel.
  bool resize_to_render = true;
  ImageSize render_size{704, 1280};
  /// Depth is clamped to [0, max_depth]; <= 0 disables the clamp.
  float max_depth = 100.0f;
  /// Pixels whose window has (max - min) / mean >= edge_threshold are dropped; <= 0 disables.
  float edge_threshold = 0.05f;
  int edge_window = 5;
};

/// Depth of `valid` pixels (valid may be empty: then depth > 0 decides) scattered to the pixel
/// round(u * to_w / from_w), round(v * to_h / from_h) — the position the pixel projects to with
/// intrinsics scaled per axis without a half-pixel shift. When several pixels land on one target,
/// the last in row-major order wins, as an indexed assignment does. Unfilled pixels are 0.
cv::Mat scatterDepthNearest(const cv::Mat& depth, const cv::Mat& valid, ImageSize to);

/// 1 where a pixel is reliable: depth > 0 and (max - min) / (mean + 1e-6) < threshold over a
/// window x window neighbourhood. Max and min ignore the outside of the image; the mean counts the
/// outside as 0 (max/avg pooling with zero padding, as GEN3C's filter does). CV_8UC1.
cv::Mat reliableDepthMask(const cv::Mat& depth, float threshold, int window);

/// The colour of the full image (CV_8UC3, `grid.image` in size) at the pixels of its stride grid,
/// (r s, c s) for grid pixel (r, c), so that a depth map on that grid is lifted with its colours;
/// `image_bgr` itself (shared, not copied) at stride 1. Throws InputError on a size or type
/// mismatch.
cv::Mat sampleImageOnGrid(const cv::Mat& image_bgr, const StrideGrid& grid);

/// Lifts every pixel with depth > 0 to P = z K^-1 [u, v, 1] with the colour of `image_bgr`
/// (CV_8UC3, same size as `depth`, CV_32FC1). Throws InputError when sizes or types disagree.
ColoredCloud backproject(const cv::Mat& depth, const cv::Mat& image_bgr,
                         const PinholeIntrinsics& k);

/// The whole preparation: kept pixels (`valid` nonzero and depth > 0; empty `valid`: depth > 0),
/// optional resize to the render size, clamp, edge filter, then lifting. `k` belongs to the depth
/// grid. Throws InputError for inconsistent sizes or when no pixel survives.
ColoredCloud buildColoredCloud(const cv::Mat& depth, const cv::Mat& valid, const cv::Mat& image_bgr,
                               const PinholeIntrinsics& k, const BackprojectionParams& params);

}  // namespace multimodal_nvs
