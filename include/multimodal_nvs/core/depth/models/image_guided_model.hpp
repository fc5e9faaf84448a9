#pragma once
// `image_guided`: returns and the geometric prior spread along the camera image, so that depth
// changes only where the image has an edge (the fast global smoother of Min et al., "Fast Global
// Image Smoothing Based on Weighted Least Squares", 2014, from OpenCV's ximgproc).
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/stride_grid.hpp"
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

struct GroundPlane;

/// `image_guided` (image_guided_model.cpp). `image`: the camera image at the grid's full image
/// size (8-bit or 16-bit, 1, 3 or 4 channels, BGR order). Throws InputError when it is missing or
/// of another size. `model_prior`: another model's prediction per grid pixel (row-major; a mean
/// of +inf or NaN where it has none) that replaces the ground and surface prior, its variance
/// standing in where only the prior speaks (guided.ground_gp_prior: ground_gp's prediction);
/// nullptr: the model's own prior.
void predictImageGuided(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params, const GroundPlane& plane,
                        const cv::Mat& image, ThreadPool& pool, PixelPredictions& out,
                        const PixelPredictions* model_prior = nullptr);

/// Another model's prediction with the image's sky (skyMask on the ground plane's horizon and the
/// returns' top rows, guided.sky_* parameters) set to guided.far_depth and variance
/// guided.sky_sigma^2. Throws InputError for an unusable image (guideOnGrid).
void applyImageSky(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                   const ImageGuidedParams& guided, const GroundPlane& plane, const cv::Mat& image,
                   PixelPredictions& out);

/// The image at the grid's pixels (u = 0, s, 2s, ...), 8-bit BGR. Throws InputError when the image
/// is empty, of another size than grid.image or of an unsupported type.
cv::Mat guideOnGrid(const cv::Mat& image, const StrideGrid& grid);

/// The sky on the grid (1 = sky): in each column, the run of pixels from the top row down to the
/// first image edge (8-bit gradient above `gradient`), the horizon (`prior` below `far_depth`) or
/// the first return (`top_return_row[c]`, rows() where the column has none), whichever comes
/// first, or the first pixel darker than `brightness` (8-bit gray) or warmer than `max_warmth`
/// (red minus blue, 8-bit). No return comes from the sky, the sky touches the top of the image and
/// is bright, and it is blue or gray, never red-tinted: a bright plain facade (beige, brick, a
/// sign) reaching the top of the image is otherwise taken for sky.
std::vector<std::uint8_t> skyMask(const cv::Mat& guide, const std::vector<float>& prior,
                                  float far_depth, const std::vector<int>& top_return_row,
                                  double gradient, double brightness, double max_warmth);

}  // namespace multimodal_nvs
