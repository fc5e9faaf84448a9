#include "multimodal_nvs/core/depth/models/image_guided_model.hpp"

// `image_guided`. Every pixel carries weighted evidence of its inverse depth: a return (weight 1,
// the nearest return where several fall into one pixel), the sky (sky_weight, at the far clamp)
// and the ground/far prior (prior_weight). The fast global smoother, guided by the image, spreads
// the three sums (w, w x, w x^2) and their ratio is the depth: a normalised convolution whose
// kernel stops at the image's edges, so a return colours its own surface and not the one behind
// it. Linear in the pixels; the smoother is OpenCV's (ximgproc) arithmetic, run on the three sums
// at once (global_smoother.hpp).
// Inverse depth: along a plane seen in perspective (the road) inverse depth is affine in the image,
// depth is not. The variance: the spread of the evidence that was mixed at the pixel (its second
// central moment, carried to depth) plus a relative std that grows from a return's to the prior's
// with the share of the prior in the pixel's evidence.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/common/global_smoother.hpp"
#include "multimodal_nvs/core/common/mask_scan.hpp"
#include "multimodal_nvs/core/common/per_worker.hpp"
#include "multimodal_nvs/core/common/vectorisable_math.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/models/nearest_model.hpp"
#include "multimodal_nvs/core/depth/return_band.hpp"
#include "multimodal_nvs/core/depth/return_density.hpp"

namespace multimodal_nvs {

cv::Mat guideOnGrid(const cv::Mat& image, const StrideGrid& grid) {
  if (image.empty()) {
    throw InputError("image_guided needs the camera image (none was given)");
  }
  if (image.rows != grid.image.height || image.cols != grid.image.width) {
    throw InputError("image_guided: the image is " + std::to_string(image.cols) + "x" +
                     std::to_string(image.rows) + ", the depth grid's image " +
                     std::to_string(grid.image.width) + "x" + std::to_string(grid.image.height));
  }
  cv::Mat eight_bit;
  if (image.depth() == CV_8U) {
    eight_bit = image;
  } else if (image.depth() == CV_16U) {
    image.convertTo(eight_bit, CV_8U, 1.0 / 256.0);
  } else {
    throw InputError("image_guided: the image must be 8-bit or 16-bit");
  }
  cv::Mat bgr;
  switch (eight_bit.channels()) {
    case 1:
      cv::cvtColor(eight_bit, bgr, cv::COLOR_GRAY2BGR);
      break;
    case 3:
      bgr = eight_bit;
      break;
    case 4:
      cv::cvtColor(eight_bit, bgr, cv::COLOR_BGRA2BGR);
      break;
    default:
      throw InputError("image_guided: the image must have 1, 3 or 4 channels");
  }
  const int s = grid.stride;
  if (s == 1) return bgr.isContinuous() ? bgr : bgr.clone();
  cv::Mat out(grid.rows(), grid.cols(), CV_8UC3);
  for (int r = 0; r < out.rows; ++r) {
    const cv::Vec3b* src = bgr.ptr<cv::Vec3b>(r * s);
    cv::Vec3b* dst = out.ptr<cv::Vec3b>(r);
    for (int c = 0; c < out.cols; ++c)
      dst[c] = src[c * s];
  }
  return out;
}

namespace {

/// Calls visit(row, col, depth) for every grid pixel within `splat_radius` of a usable return's
/// (rounded) pixel; returns how many returns fell on the grid. Through the pinhole model (lens
/// distortion is not applied here): the grid is the image's, subsampled. Returns outside the
/// grid's columns are skipped before any tangent (azimuthWindow): a 360-degree LiDAR sweep has ~5x
/// more of them than returns in view.
template <class Visit>
std::size_t forEachReturnPixel(const std::vector<AngularSample>& samples,
                               const PixelAngleGrid& angles, int splat_radius, Visit&& visit) {
  const StrideGrid& grid = angles.grid();
  const PinholeIntrinsics& k = angles.intrinsics();
  const int rows = grid.rows(), cols = grid.cols();
  PinholeIntrinsics pinhole = k;
  pinhole.distortion = {};
  const AzimuthWindow window =
      azimuthWindow(pinhole, -0.5 * grid.stride, (double(cols) - 0.5) * grid.stride);
  std::size_t in_view = 0;
  for (const AngularSample& s : samples) {
    if (!(s.depth > 0.0f) || !std::isfinite(s.depth) || !window.contains(s.azimuth_deg)) continue;
    const Eigen::Vector2d xy = normalisedFromAngles(s.azimuth_deg, s.elevation_deg);
    const double u = (k.fx * xy.x() + k.cx) / grid.stride;
    const double v = (k.fy * xy.y() + k.cy) / grid.stride;
    if (!(u > -0.5 && v > -0.5 && u < cols - 0.5 && v < rows - 0.5)) continue;
    const int c0 = static_cast<int>(std::lround(u)), r0 = static_cast<int>(std::lround(v));
    ++in_view;
    for (int r = std::max(0, r0 - splat_radius); r <= std::min(rows - 1, r0 + splat_radius); ++r) {
      for (int c = std::max(0, c0 - splat_radius); c <= std::min(cols - 1, c0 + splat_radius); ++c)
        visit(r, c, s.depth);
    }
  }
  return in_view;
}

/// The nearest return per grid pixel where one fell, and per column the top row of a return. A
/// list, not a full-size raster: radar puts a few hundred returns into VoD's 2.35 M pixels.
struct ReturnPixels {
  std::vector<std::pair<std::size_t, float>> nearest;  // (pixel index, depth), each pixel once
  std::vector<int> top_row;
  std::size_t in_view = 0;  // returns that fell on the grid (several may share a pixel)
};

ReturnPixels returnPixels(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                          int splat_radius) {
  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  ReturnPixels pixels;
  pixels.top_row.assign(cols, rows);
  pixels.in_view =
      forEachReturnPixel(samples, angles, splat_radius, [&](int r, int c, float depth) {
        pixels.nearest.emplace_back(std::size_t(r) * cols + c, depth);
        pixels.top_row[c] = std::min(pixels.top_row[c], r);
      });
  // By pixel, the nearest first; then each pixel's first entry alone.
  std::sort(pixels.nearest.begin(), pixels.nearest.end());
  pixels.nearest.erase(std::unique(pixels.nearest.begin(), pixels.nearest.end(),
                                   [](const auto& a, const auto& b) { return a.first == b.first; }),
                       pixels.nearest.end());
  return pixels;
}

/// The elevation (degrees) of each return's pixel.
std::vector<float> returnElevations(const ReturnPixels& returns, const PixelAngleGrid& angles) {
  const int cols = angles.grid().cols();
  std::vector<float> elevations;
  elevations.reserve(returns.nearest.size());
  for (const auto& [pixel, depth] : returns.nearest)
    elevations.push_back(angles.elevationRow(int(pixel / cols))[pixel % cols]);
  return elevations;
}

/// returnPixels' top_row alone (the sky test needs no return depths).
std::vector<int> topReturnRows(const std::vector<AngularSample>& samples,
                               const PixelAngleGrid& angles, int splat_radius) {
  std::vector<int> top_row(angles.grid().cols(), angles.grid().rows());
  forEachReturnPixel(samples, angles, splat_radius,
                     [&](int r, int c, float) { top_row[c] = std::min(top_row[c], r); });
  return top_row;
}

/// skyMask with the model's sky parameters: the one place that says which parameters make the test
/// (image_guided's own sky and ground_gp's, imageSkyMask).
std::vector<std::uint8_t> skyMaskOf(const cv::Mat& guide, const PriorRowFunction& prior_row,
                                    const std::vector<int>& top_return_row,
                                    const ImageGuidedParams& g, ThreadPool& pool) {
  return skyMask(guide, prior_row, static_cast<float>(g.far_depth), top_return_row, g.sky_gradient,
                 g.sky_brightness, g.sky_max_warmth, &pool);
}

float medianDepth(const std::vector<AngularSample>& samples) {
  std::vector<float> d;
  for (const AngularSample& s : samples) {
    if (s.depth > 0.0f && std::isfinite(s.depth)) d.push_back(s.depth);
  }
  if (d.empty()) return 10.0f;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

/// The surface prior: each pixel's prior becomes the nearer of itself and the surface of its
/// angularly nearest return (not in the sky). With `lateral_prior` a return whose pixel lies
/// nearer the image centre than the return continues as a wall along the viewing direction: the
/// return's lateral offset X is constant along a wall parallel to the optical axis (a street's
/// facades, a row of parked cars), so the pixel's depth there is X / x (x = X / Z, its normalised
/// image coordinate), whatever the pitch. Without it the far end of a facade whose only returns
/// are near takes their depth, which is too near (the "minimum of the nearest surface" error).
void applySurfacePrior(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                       const ImageGuidedParams& g, float far, const std::vector<std::uint8_t>& sky,
                       ThreadPool& pool, std::vector<float>& prior) {
  const std::vector<AngularSample> usable = usableSamples(samples);
  if (usable.empty()) return;
  const std::vector<int> nearest = nearestSampleIndex(usable, angles, pool);
  std::vector<float> lateral_x(usable.size());  // the return's normalised x = X / Z
  for (std::size_t s = 0; s < usable.size(); ++s) {
    lateral_x[s] = static_cast<float>(
        normalisedFromAngles(usable[s].azimuth_deg, usable[s].elevation_deg).x());
  }
  const int rows = angles.grid().rows(), cols = angles.grid().cols();
  pool.parallelFor(
      rows,
      [&](long long r, int) {
        for (int c = 0; c < cols; ++c) {
          const std::size_t i = std::size_t(r) * cols + c;
          if (!sky.empty() && sky[i]) continue;
          const int s = nearest[i];
          float depth = usable[s].depth;
          if (g.lateral_prior) {
            const float x = static_cast<float>(angles.normalisedRay(int(r), c).x());
            const float x_return = lateral_x[s];
            // Same side of the centre, nearer to it: farther along the wall (X / x > Z).
            if (x * x_return > 0.0f && std::abs(x) < std::abs(x_return)) {
              depth = std::min(depth * (x_return / x), far);
            }
          }
          prior[i] = std::min(prior[i], depth);
        }
      },
      16);
}

/// The smoother on the evidence sums with `lambda` (already per output grid pixel), on a grid
/// `smooth_scale` times coarser than the output when asked: the sums are averaged over each coarse
/// cell (they are sums: averaging keeps their ratios), smoothed with lambda / scale^2 (the
/// smoother's reach, in pixels, grows with sqrt(lambda): the same reach on the image) and
/// interpolated back bilinearly.
void smoothSums(const cv::Mat& guide, const ImageGuidedParams& g, double lambda,
                bool vertical_edges, ThreadPool& pool, std::vector<cv::Mat>& sums) {
  const int scale = g.smooth_scale;
  if (scale <= 1) {
    smoothAlongGuide(guide, sums, {lambda, g.sigma_color, 0.25, g.iterations, vertical_edges},
                     pool);
    return;
  }
  const cv::Size coarse((guide.cols + scale - 1) / scale, (guide.rows + scale - 1) / scale);
  cv::Mat coarse_guide;
  cv::resize(guide, coarse_guide, coarse, 0, 0, cv::INTER_AREA);
  std::vector<cv::Mat> coarse_sums(sums.size());
  for (std::size_t k = 0; k < sums.size(); ++k)
    cv::resize(sums[k], coarse_sums[k], coarse, 0, 0, cv::INTER_AREA);
  smoothAlongGuide(
      coarse_guide, coarse_sums,
      {lambda / (double(scale) * scale), g.sigma_color, 0.25, g.iterations, vertical_edges}, pool);
  for (std::size_t k = 0; k < sums.size(); ++k)
    cv::resize(coarse_sums[k], sums[k], sums[k].size(), 0, 0, cv::INTER_LINEAR);
}

/// prior[c] = min(model[c], far) wherever the model's depth is positive and finite, -1 elsewhere;
/// returns how many pixels it left to the own prior. A function of its own with restrict pointers
/// so that it vectorises (in the row lambda it stayed scalar).
int takeOverModelPrior(const float* __restrict model, float far, int cols,
                       float* __restrict prior) {
  int unusable = 0;
  for (int c = 0; c < cols; ++c) {
    const float d = model[c];
    const bool usable = d > 0.0f && isFiniteVectorisable(d);
    prior[c] = usable ? minOf(d, far) : -1.0f;
    unusable += !usable;
  }
  return unusable;
}

/// One row of the prior's evidence sums (w, w x, w x^2; x = 1 / depth), the prior weighing
/// `prior_weight[c]` at pixel c. The returns are added afterwards (addReturnEvidence).
void priorEvidenceRow(const float* __restrict prior, float far,
                      const float* __restrict prior_weight, int cols, float* __restrict sum_w,
                      float* __restrict sum_wx, float* __restrict sum_wxx) {
  for (int c = 0; c < cols; ++c) {
    const float xp = 1.0f / std::min(prior[c], far);
    sum_w[c] = prior_weight[c];
    sum_wx[c] = prior_weight[c] * xp;
    sum_wxx[c] = prior_weight[c] * xp * xp;
  }
}

/// The prior's weight per grid pixel: `weight`, times `above_factor` at the pixels whose
/// elevation lies above `band_top` (degrees; NaN: nowhere).
class PriorWeights {
 public:
  PriorWeights(const PixelAngleGrid& angles, float weight, float band_top, float above_factor)
      : angles_(angles),
        band_top_(band_top),
        below_(angles.grid().cols(), weight),
        above_(angles.grid().cols(), weight * above_factor) {}

  /// Row r's weights: one of two constant rows where the whole row lies on one side of the band
  /// (most rows), else written into `scratch` (cols floats).
  const float* row(int r, float* __restrict scratch) const {
    // NaN compares false: no pixel is above an unknown band.
    if (!(angles_.maxElevation(r) > band_top_)) return below_.data();
    if (angles_.minElevation(r) > band_top_) return above_.data();
    const int cols = angles_.grid().cols();
    const float* __restrict elevation = angles_.elevationRow(r);
    const float below = below_[0], above = above_[0];
    for (int c = 0; c < cols; ++c)
      scratch[c] = elevation[c] > band_top_ ? above : below;
    return scratch;
  }

 private:
  const PixelAngleGrid& angles_;
  float band_top_;
  std::vector<float> below_, above_;
};

// With ground_gp's prediction as the prior, a return whose depth is less than the prior's at its
// pixel by this factor weighs kIsolatedFrontWeight instead of 1. That prior is the nearest surface
// among the pixel's neighbouring returns, so such a return has no neighbour that agrees with it:
// radar clutter and multipath drawn at a random range, not a surface (real radars put 0-6 % of
// their returns 20 % or more in front of the LiDAR's surface, against 42-51 % behind it). Measured
// at stride 1 (radar MAE m, mean over frames): VoD 00549/01047 3.205 -> 3.164, Astyx 4.425 ->
// 4.432, nuScenes 5.500 unchanged; the synthetic scenes' novel views within 0.06 dB each.
constexpr float kIsolatedFrontRatio = 1.6f;
constexpr float kIsolatedFrontWeight = 0.1f;

/// A return's evidence (weight 1) added to the prior's at its pixel; with `isolated_in_front`, a
/// return far in front of the prior there (the sums hold only the prior's evidence until now)
/// weighs kIsolatedFrontWeight.
void addReturnEvidence(const ReturnPixels& returns, bool isolated_in_front,
                       std::vector<cv::Mat>& sums) {
  float *sum_w = sums[0].ptr<float>(0), *sum_wx = sums[1].ptr<float>(0),
        *sum_wxx = sums[2].ptr<float>(0);
  // Each pixel holds at most one return (returnPixels), so every prior read here is the prior's.
  for (const auto& [i, depth] : returns.nearest) {
    const float x = 1.0f / depth;
    // depth * ratio < prior depth = sum_w / sum_wx, written without the division (sum_w > 0).
    const bool in_front =
        isolated_in_front && sum_w[i] > 0.0f && depth * kIsolatedFrontRatio * sum_wx[i] < sum_w[i];
    const float w = in_front ? kIsolatedFrontWeight : 1.0f;
    sum_w[i] = sum_w[i] + w;
    sum_wx[i] = sum_wx[i] + w * x;
    sum_wxx[i] = sum_wxx[i] + w * x * x;
  }
}

/// The model's own prior before the surfaces: the ground plane's (guided.ground_prior) or the
/// returns' median depth everywhere, a row at a time or as a plane.
class OwnPrior {
 public:
  OwnPrior(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
           const GroundPlane& plane, const ImageGuidedParams& g)
      : angles_(angles),
        ground_(g.ground_prior ? std::make_unique<GroundPriorRows>(angles, plane, g.far_depth)
                               : nullptr),
        median_(g.ground_prior ? 0.0f : medianDepth(samples)) {}
  void row(int r, float* out) const {
    if (ground_) {
      ground_->row(r, out);
    } else {
      std::fill(out, out + angles_.grid().cols(), median_);
    }
  }
  std::vector<float> plane(ThreadPool& pool) const {
    const int rows = angles_.grid().rows(), cols = angles_.grid().cols();
    std::vector<float> out(std::size_t(rows) * cols);
    pool.parallelFor(
        rows, [&](long long r, int) { row(int(r), out.data() + r * cols); }, 16);
    return out;
  }

 private:
  const PixelAngleGrid& angles_;
  std::unique_ptr<GroundPriorRows> ground_;
  float median_;
};

struct DepthFromEvidence {
  float far;
  float prior_weight;     // per grid pixel, without the factor above the returns (the floor)
  float return_relative;  // a return's relative std
  float prior_relative;   // the prior's relative std
};

/// One row of depth and variance from the smoothed sums: depth = 1 / (sum w x / sum w); the
/// variance is the spread of the mixed evidence carried to depth (var(d) ~ var(x) / x^4, first
/// order) plus a relative std between a return's and the prior's by the prior's share of the
/// weight; with another model as the prior (kModelPrior), its own variance where only it speaks.
/// Branch-free (both cases computed, one selected) so that it vectorises; the sky is written by
/// the caller afterwards (writeSky): with the sky's byte mask scanned in this function, GCC 12 kept
/// the model-prior loop scalar ("control flow in loop"), ~14 % of the radar default at VoD's full
/// resolution.
template <bool kModelPrior>
void depthFromEvidenceRow(const DepthFromEvidence& e, const float* __restrict prior_weight,
                          const float* __restrict sum_w, const float* __restrict sum_wx,
                          const float* __restrict sum_wxx, const float* __restrict prior_variance,
                          int cols, float* __restrict mean, float* __restrict variance) {
  // The smoother keeps sums positive up to rounding; the floor keeps the ratio finite.
  const float weight_floor = e.prior_weight * 1e-3f, x_floor = 1.0f / e.far;
  for (int c = 0; c < cols; ++c) {
    const float w = maxOf(sum_w[c], weight_floor);
    const float x = maxOf(sum_wx[c] / w, x_floor);
    const float spread_x = maxOf(sum_wxx[c] / w - x * x, 0.0f);
    const float depth = minOf(1.0f / x, e.far);
    const float prior_share = minOf(1.0f, prior_weight[c] / w);
    const float mixing = spread_x * depth * depth * depth * depth;
    const float relative = e.return_relative + (e.prior_relative - e.return_relative) * prior_share;
    float v = mixing + (relative * depth) * (relative * depth);
    if constexpr (kModelPrior) {
      // Another model's prior brings its own (calibrated) variance: it holds where only the
      // prior speaks, a return's relative std where the returns do.
      const float at_return = e.return_relative * depth;
      const float with_prior =
          mixing + prior_share * prior_variance[c] + (1.0f - prior_share) * at_return * at_return;
      v = isFiniteVectorisable(prior_variance[c]) ? with_prior : v;
    }
    mean[c] = depth;
    variance[c] = v;
  }
}

/// The sky's depth (the far clamp) and variance at the set bytes of `sky` (`count` pixels from
/// `mean` and `variance`): the one place that says what a sky pixel gets, for a row or an image.
void writeSky(const std::uint8_t* sky, int count, const ImageGuidedParams& g, float* mean,
              float* variance) {
  const float far = static_cast<float>(g.far_depth);
  const float sky_variance = static_cast<float>(g.sky_sigma * g.sky_sigma);
  forEachSetByte(sky, count, [&](int i) {
    mean[i] = far;
    variance[i] = sky_variance;
  });
}

}  // namespace

std::vector<std::uint8_t> imageSkyMask(const std::vector<AngularSample>& samples,
                                       const PixelAngleGrid& angles, const ImageGuidedParams& g,
                                       const GroundPlane& plane, const cv::Mat& image,
                                       ThreadPool& pool) {
  const GroundPriorRows ground(angles, plane, g.far_depth);
  return skyMaskOf(
      guideOnGrid(image, angles.grid()), [&](int r, float* out) { ground.row(r, out); },
      topReturnRows(samples, angles, g.splat_radius_px), g, pool);
}

void applySkyMask(const std::vector<std::uint8_t>& sky, const ImageGuidedParams& g,
                  PixelPredictions& out) {
  if (sky.size() != out.mean.size() || sky.size() != out.variance.size())
    throw InputError("applySkyMask: the sky mask and the prediction differ in size");
  writeSky(sky.data(), static_cast<int>(sky.size()), g, out.mean.data(), out.variance.data());
}

ImageGuidedReport predictImageGuided(const std::vector<AngularSample>& samples,
                                     const PixelAngleGrid& angles,
                                     const DepthCompletionParams& params,
                                     const GroundChoice& ground, const cv::Mat& image,
                                     ThreadPool& pool, PixelPredictions& out,
                                     const PredictionRows* model_prior) {
  const GroundPlane& plane = ground.plane;
  const ImageGuidedParams& g = params.guided;
  const StrideGrid& grid = angles.grid();
  const int rows = grid.rows(), cols = grid.cols();
  const std::size_t n = std::size_t(rows) * cols;
  if (model_prior != nullptr && (model_prior->rows() != rows || model_prior->cols() != cols))
    throw InputError("image_guided: the model prior has the wrong size");
  const cv::Mat guide = guideOnGrid(image, grid);
  const float far = static_cast<float>(g.far_depth);
  const OwnPrior own_prior(samples, angles, plane, g);
  const ReturnPixels returns = returnPixels(samples, angles, g.splat_radius_px);
  // Another model's prediction (ground_gp's) as the prior already holds the ground, the nearest
  // surfaces and its own fit to the returns; the smoother adds the image's edges. It is read row by
  // row in the evidence pass, and the own prior is needed only where that model has no depth and
  // for the sky (above the ground): a row at a time, no plane of it.
  std::vector<float> prior;
  if (model_prior == nullptr) prior = own_prior.plane(pool);
  std::vector<std::uint8_t> sky;
  // The sky reads the own prior's rows above the ground (those of `prior`, before the surfaces).
  if (g.sky) {
    sky = skyMaskOf(
        guide, [&](int r, float* out) { own_prior.row(r, out); }, returns.top_row, g, pool);
  }
  if (model_prior == nullptr && g.surface_prior)
    applySurfacePrior(samples, angles, g, far, sky, pool, prior);
  // Evidence sums per pixel, one plane each: weight, weight * x, weight * x^2 with x = 1 / depth.
  std::vector<cv::Mat> sums(3);
  for (cv::Mat& plane : sums)
    plane.create(rows, cols, CV_32F);
  // lambda and prior_weight are per image pixel; a grid pixel at output stride s stands for s^2
  // of them. So the prior weighs s^2 times more per grid pixel (a return still weighs 1: it falls
  // into one grid pixel at any stride), and the smoother takes lambda / s^2, the same reach on the
  // image. Without this a stride-2 grid spread each return twice as far against a quarter of the
  // prior (radar, 100 % kept, MAE m: Astyx 5.02 at stride 1, 6.72 at stride 2; now 5.02 at both).
  // With ground_gp's prediction as the prior, its weight also follows how densely the returns
  // cover the view (return_density.hpp); the own prior (dense input) keeps prior_weight: on LiDAR
  // the factor (at its cap, ten) raised the MAE on every real set, by up to 7 %.
  const double grid_pixel_area = double(grid.stride) * grid.stride;
  const double density = returnDensity(returns.in_view, angles.intrinsics(), grid.image);
  const double weight = model_prior != nullptr ? priorWeightForDensity(g.prior_weight, density,
                                                                       g.prior_reference_density)
                                               : g.prior_weight;
  const float prior_weight = static_cast<float>(weight * grid_pixel_area);
  // Above the returns' band the smoother would only extrapolate the returns below it upward;
  // ground_gp's prior weighs more there (ImageGuidedParams::prior_weight_above_returns). A 2D
  // scanner's returns all lie on its plane's rows: no band to speak of.
  const bool weigh_above_band =
      model_prior != nullptr && !ground.single_scan_plane && g.prior_weight_above_returns != 1.0;
  const float band_top =
      weigh_above_band ? returnBandTop(returnElevations(returns, angles)) : std::nanf("");
  const PriorWeights prior_weights(angles, prior_weight, band_top,
                                   static_cast<float>(g.prior_weight_above_returns));
  // Per worker: the prior's weights of a row; with a model prior, the own prior's row, the
  // model's row and the prior taken over from it.
  PerWorker<std::vector<float>> weight_rows(pool.size(), std::vector<float>(cols));
  PerWorker<std::vector<float>> row_scratch(model_prior != nullptr ? pool.size() : 0,
                                            std::vector<float>(3 * std::size_t(cols)));
  pool.parallelFor(
      rows,
      [&](long long row, int worker) {
        const int r = static_cast<int>(row);
        const std::size_t begin = std::size_t(r) * cols;
        const float* prior_row = prior.data() + begin;
        if (model_prior != nullptr) {
          float* own = row_scratch[worker].data();
          float* taken = own + cols;
          const int unusable =
              takeOverModelPrior(model_prior->mean(r, taken + cols), far, cols, taken);
          // The own prior where the model has no depth, and at the sky: it keeps its own prior
          // (the far clamp) as its evidence, so that it does not pull its edge nearer. Most rows
          // have neither: the own prior's row is computed only for those that do.
          const std::uint8_t* sky_row = sky.empty() ? nullptr : sky.data() + begin;
          const bool has_sky = sky_row != nullptr && std::memchr(sky_row, 1, cols) != nullptr;
          if (unusable > 0 || has_sky) {
            own_prior.row(r, own);
            for (int c = 0; c < cols; ++c)
              taken[c] = taken[c] < 0.0f ? own[c] : taken[c];
            if (has_sky) forEachSetByte(sky_row, cols, [&](int c) { taken[c] = own[c]; });
          }
          prior_row = taken;
        }
        const float* weights = prior_weights.row(r, weight_rows[worker].data());
        priorEvidenceRow(prior_row, far, weights, cols, sums[0].ptr<float>(r),
                         sums[1].ptr<float>(r), sums[2].ptr<float>(r));
      },
      16);
  addReturnEvidence(returns, model_prior != nullptr, sums);
  const cv::Mat edge_guide = g.edges ? guide : cv::Mat(rows, cols, CV_8UC3, cv::Scalar::all(128));
  // A 2D scanner's returns (all on one scan plane) project to its plane's rows, not to their
  // surfaces' (their elevation is not measured): the image's edges between rows say nothing about
  // which surface a return's evidence belongs to, its edges between columns still do. On nuScenes'
  // front radar, radar MAE at stride 1: 6.01 m following every edge, 5.50 following only those
  // between columns, 5.48 with a uniform guide (which would also drop the azimuth's edges).
  const bool vertical_edges = !ground.single_scan_plane;
  smoothSums(edge_guide, g, g.lambda / grid_pixel_area, vertical_edges, pool, sums);

  out.mean.resize(n);
  out.variance.resize(n);
  const DepthFromEvidence to_depth{far, prior_weight, static_cast<float>(g.return_relative_sigma),
                                   static_cast<float>(g.relative_sigma)};
  pool.parallelFor(
      rows,
      [&](long long row, int worker) {
        const int r = static_cast<int>(row);
        const std::size_t i = std::size_t(r) * cols;
        const std::uint8_t* sky_row = sky.empty() ? nullptr : sky.data() + i;
        const float *sum_w = sums[0].ptr<float>(r), *sum_wx = sums[1].ptr<float>(r),
                    *sum_wxx = sums[2].ptr<float>(r);
        const float* weights = prior_weights.row(r, weight_rows[worker].data());
        if (model_prior != nullptr) {
          depthFromEvidenceRow<true>(to_depth, weights, sum_w, sum_wx, sum_wxx,
                                     model_prior->variance(r, row_scratch[worker].data()), cols,
                                     out.mean.data() + i, out.variance.data() + i);
        } else {
          depthFromEvidenceRow<false>(to_depth, weights, sum_w, sum_wx, sum_wxx, nullptr, cols,
                                      out.mean.data() + i, out.variance.data() + i);
        }
        if (sky_row != nullptr)
          writeSky(sky_row, cols, g, out.mean.data() + i, out.variance.data() + i);
      },
      16);
  return {density, weight, band_top};
}

}  // namespace multimodal_nvs
