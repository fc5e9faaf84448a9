#pragma once
// The camera image's colours for the nearest-surface prior: which of a pixel's nearest returns
// lie on a surface that looks like the pixel.
#include <array>
#include <cstddef>
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

/// A colour (B, G, R, 0..255); NaN in the first channel where there is none (outside the image).
using CellColour = std::array<float, 3>;

/// The image's colour averaged over square cells of kCellPx pixels (aligned to the image's
/// origin), so that a colour stands for a patch of a surface rather than one pixel of its texture
/// (window frames, lane markings), and so that a return projected a pixel or two off its surface
/// still reads that surface's colour.
class SurfaceColours {
 public:
  static constexpr int kCellPx = 4;

  /// `image`: the camera image at full resolution (`size`, the depth grid's image), 8- or 16-bit,
  /// 1, 3 or 4 channels (InputError otherwise, as image_guided: colours read from a mis-sized
  /// image would be another pixel's); `sigma`: the colour distance (0..255 per channel, Euclidean)
  /// at which a sample's weight falls to exp(-1/2) of a matching one's.
  SurfaceColours(const cv::Mat& image, const ImageSize& size, double sigma);

  /// The colour of the cell that holds full-image pixel (u, v); NaN outside the image.
  CellColour at(double u, double v) const;
  /// The colour at each sample's pixel (through the camera model of `angles`).
  std::vector<CellColour> atSamples(const std::vector<AngularSample>& samples,
                                    const PixelAngleGrid& angles) const;
  /// How much a sample of colour `sample` counts for a pixel of colour `pixel`: 1 for the same
  /// colour, falling as a Gaussian of their distance to kWeightFloor; 1 when either is unknown.
  float weight(const CellColour& pixel, const CellColour& sample) const;

  /// A sample of another colour keeps this weight, so that a pixel with no look-alike among its
  /// nearest samples falls back to the plain order statistic.
  static constexpr float kWeightFloor = 0.05f;

 private:
  cv::Mat bgr_;  // the image, 8-bit BGR
  float inv_two_sigma2_ = 0.0f;
};

/// The value at which the depth-sorted cumulative weight of (depths, weights) first reaches
/// `fraction` of the total: with equal weights and fraction (rank - 0.5) / n the rank-th smallest
/// depth (1 = smallest), the plain order statistic. Reorders both vectors; at least one value.
float weightedOrderStatistic(std::vector<float>& depths, std::vector<float>& weights,
                             double fraction);

}  // namespace multimodal_nvs
