#pragma once
// The image's sky: where no return can come from, sent to the far clamp by the models.
#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"

namespace multimodal_nvs {

/// The sky on the grid (1 = sky): in each column, the run of pixels from the top row down to the
/// first image edge (8-bit gradient above `gradient`), the horizon (`prior` below `far_depth`) or
/// the first return (`top_return_row[c]`, rows() where the column has none), whichever comes
/// first, or the first pixel darker than `brightness` (8-bit gray) or warmer than `max_warmth`
/// (red minus blue, 8-bit). No return comes from the sky, the sky touches the top of the image and
/// is bright, and it is blue or gray, never red-tinted: a bright plain facade (beige, brick, a
/// sign) reaching the top of the image is otherwise taken for sky.
/// `guide`: 8-bit BGR on the grid; `prior_row(r, out)` writes the prior's row r (one float per
/// guide column): called for the rows above the ground only, so that a caller need not compute a
/// whole image of it. The gradient is the 3x3 Sobel's (OpenCV's, reflected at the image's borders)
/// divided by 8: the step per pixel. `pool`: runs the passes in parallel when given; the mask
/// does not depend on it.
using PriorRowFunction = std::function<void(int row, float* out)>;
std::vector<std::uint8_t> skyMask(const cv::Mat& guide, const PriorRowFunction& prior_row,
                                  float far_depth, const std::vector<int>& top_return_row,
                                  double gradient, double brightness, double max_warmth,
                                  ThreadPool* pool = nullptr);

/// skyMask with the prior as a plane (row-major, one per guide pixel).
std::vector<std::uint8_t> skyMask(const cv::Mat& guide, const std::vector<float>& prior,
                                  float far_depth, const std::vector<int>& top_return_row,
                                  double gradient, double brightness, double max_warmth,
                                  ThreadPool* pool = nullptr);

}  // namespace multimodal_nvs
