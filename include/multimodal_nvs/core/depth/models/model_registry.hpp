#pragma once
// The one place that maps a DepthModel to its implementation. Adding a model: a file pair in this
// folder, an entry in DepthModel (depth_params.hpp) and a case in predictWithModel.
#include <opencv2/core.hpp>
#include <vector>
#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/models/model_scratch.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

struct GroundChoice;
struct ImageGuidedReport;

/// True for nearest, linear, ipbasic and constant (the models that need no neighbour sets).
bool isBaseline(DepthModel model);

/// The largest sets of ground_gp's residual GP when it switches to the tile approximation by
/// itself (max_neighbors = 0). On the 12 Astyx frames 8, 16 and 32 differ from the exact GP by
/// about as much (README, ground_gp), and 8 is the fastest.
constexpr int kAutoMaxNeighbors = 8;

/// Whether ground_gp's sparse mode solves its residual GP with the tile approximation:
/// max_neighbors > 0, or the neighbour sets are large (meanSamplesWithinRadius above
/// kLargeNeighbourSetMean). VoD and nuScenes radar stay exact.
bool groundGpUsesTiles(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                       const DepthCompletionParams& params);

/// Runs `params.model` on the samples into `out`. `shift` is the targets' centre (computeShift of
/// params.shift). `image`: the camera image (used by image_guided only; may be empty for the
/// others). Returns the number of neighbour sets (or tiles) the model solved, 0 for models
/// without any.
/// For ground_gp, `ground` (when given) receives the plane and mode it chose; for image_guided,
/// `guided` (when given) its prior's weight. `scratch` (when given) holds work buffers between
/// calls.
int predictWithModel(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const DepthCompletionParams& params, double shift, ThreadPool& pool,
                     PixelPredictions& out, const cv::Mat& image = cv::Mat(),
                     GroundChoice* ground = nullptr, ModelScratch* scratch = nullptr,
                     ImageGuidedReport* guided = nullptr);

}  // namespace multimodal_nvs
