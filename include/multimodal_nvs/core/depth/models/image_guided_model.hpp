#pragma once
// `image_guided`: returns and the geometric prior spread along the camera image, so that depth
// changes only where the image has an edge (the fast global smoother of Min et al., "Fast Global
// Image Smoothing Based on Weighted Least Squares", 2014, from OpenCV's ximgproc).
#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/models/prediction_upsampling.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"
#include "multimodal_nvs/core/depth/sky_mask.hpp"

namespace multimodal_nvs {

struct GroundChoice;
struct GroundPlane;

/// What image_guided chose for a frame, for the node's stats and the tools' JSON: a user with
/// another sensor sees how its density moved the prior's weight.
struct ImageGuidedReport {
  /// Returns in the camera's view per square degree (returnDensity).
  double return_density = -1.0;
  /// The prior's evidence weight per image pixel this frame used: guided.prior_weight, times the
  /// density's factor with ground_gp's prior (priorWeightForDensity).
  double prior_weight = -1.0;
  /// The top of the returns' band (degrees of elevation) above which the prior weighed
  /// prior_weight_above_returns times more; NaN where it weighed the same everywhere.
  double band_top_deg = std::numeric_limits<double>::quiet_NaN();
};

/// `image_guided` (image_guided_model.cpp). `ground`: chooseGround's plane (the ground prior and
/// the sky's horizon) and whether the returns lie on one scan plane (then the smoother's vertical
/// solves ignore the image: such returns' rows are not measured). `image`: the camera image at
/// the grid's full image
/// size (8-bit or 16-bit, 1, 3 or 4 channels, BGR order). Throws InputError when it is missing or
/// of another size. `model_prior`: another model's prediction on the grid, read row by row (a
/// mean of +inf or NaN where it has none), that replaces the ground and surface prior, its
/// variance standing in where only the prior speaks (guided.ground_gp_prior: ground_gp's
/// prediction, possibly interpolated from a coarser grid as it is read); nullptr: the model's own
/// prior. Throws InputError when it is not of the grid's size.
/// Returns what the frame made of the prior's weight (ImageGuidedReport).
ImageGuidedReport predictImageGuided(const std::vector<AngularSample>& samples,
                                     const PixelAngleGrid& angles,
                                     const DepthCompletionParams& params,
                                     const GroundChoice& ground, const cv::Mat& image,
                                     ThreadPool& pool, PixelPredictions& out,
                                     const PredictionRows* model_prior = nullptr);

/// The image's sky on the grid for another model's prediction (skyMask on the ground plane's
/// horizon and the returns' top rows, guided.sky_* parameters): 1 where sky. It does not depend on
/// the prediction, so it can be computed while the prediction is still being made. Throws
/// InputError for an unusable image (guideOnGrid).
std::vector<std::uint8_t> imageSkyMask(const std::vector<AngularSample>& samples,
                                       const PixelAngleGrid& angles,
                                       const ImageGuidedParams& guided, const GroundPlane& plane,
                                       const cv::Mat& image, ThreadPool& pool);

/// The prediction with imageSkyMask()'s sky set to guided.far_depth and variance
/// guided.sky_sigma^2.
void applySkyMask(const std::vector<std::uint8_t>& sky, const ImageGuidedParams& guided,
                  PixelPredictions& out);

/// The image at the grid's pixels (u = 0, s, 2s, ...), 8-bit BGR. Throws InputError when the image
/// is empty, of another size than grid.image or of an unsupported type.
cv::Mat guideOnGrid(const cv::Mat& image, const StrideGrid& grid);

}  // namespace multimodal_nvs
