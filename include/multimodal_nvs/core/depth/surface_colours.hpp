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
  /// The colour at a sample's pixel (through the camera model of `angles`).
  CellColour atSample(const AngularSample& sample, const PixelAngleGrid& angles) const;
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

/// Which of (depths, weights) is the one at which the depth-sorted cumulative weight first
/// reaches `fraction` of the total (its index): with equal weights and fraction (rank - 0.5) / n
/// the rank-th smallest depth (1 = smallest), the plain order statistic. At least one value.
std::size_t weightedOrderStatistic(const std::vector<float>& depths,
                                   const std::vector<float>& weights, double fraction);

/// The nearest-surface prior's use of the image (nearestSurfaceRows): its returns weighed by
/// colour, and, with `walls`, a return that looks like the pixel continued as a wall along the
/// viewing direction towards the image centre (the lateral offset X = x z of a facade or a row of
/// parked cars is constant along it, so a pixel at normalised x there lies at X / x, capped at
/// `wall_cap_m`), as image_guided's own prior does (lateral_prior) but only across its colour.
struct SurfacePriorImage {
  const SurfaceColours* colours = nullptr;  ///< nullptr: no image, every return counts the same
  bool walls = false;
  double wall_cap_m = 100.0;
  /// > 0: a lattice node whose chosen return does not look like it takes the look-alike return of
  /// the nearest node along its row or column within this angle (degrees) that found one
  /// (look_alike_fill.hpp); 0: off
  double fill_deg = 0.0;
};

/// The wall rule of SurfacePriorImage: the depth at a pixel of normalised column x `pixel_x` of a
/// wall through a return at `return_x` and `return_depth`, when the pixel lies between the return
/// and the image centre (same side, nearer the axis) and the return is at least
/// kWallMinOffAxis off it; otherwise `return_depth`. Capped at `cap`.
double wallDepth(double return_x, double return_depth, double pixel_x, double cap);
/// A return this close to the optical axis (normalised x) is not continued as a wall: the back of
/// a vehicle ahead, not a facade along the street.
constexpr double kWallMinOffAxis = 0.05;
/// The colour weight (SurfaceColours::weight) a return needs to be continued as the pixel's wall.
constexpr float kWallMinColourWeight = 0.5f;

}  // namespace multimodal_nvs
