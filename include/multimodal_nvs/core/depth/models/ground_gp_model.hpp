#pragma once
// `ground_gp`: the local GP on the residual around a ground-plane and nearest-surface prior.
#include <opencv2/core.hpp>
#include <vector>

#include "multimodal_nvs/core/common/thread_pool.hpp"
#include "multimodal_nvs/core/depth/angular_samples.hpp"
#include "multimodal_nvs/core/depth/angular_triangulation.hpp"
#include "multimodal_nvs/core/depth/depth_params.hpp"
#include "multimodal_nvs/core/depth/models/model_scratch.hpp"
#include "multimodal_nvs/core/depth/models/pixel_predictions.hpp"
#include "multimodal_nvs/core/depth/neighbour_sets.hpp"
#include "multimodal_nvs/core/depth/pixel_angle_grid.hpp"

namespace multimodal_nvs {

struct GroundPlane;
/// `ground_gp`: local GP on the residual around the ground-plane prior (ground_gp_model.cpp).
/// `sets`: the exact residual GP on these neighbour sets; nullptr: the tile approximation
/// (predictTiledLocalGp with params.max_neighbors samples per tile), for large neighbour sets.
/// `image` (may be empty): the camera image, for the nearest-surface prior's colour weighting
/// (ground.surface_colour_sigma > 0).
void predictGroundGp(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const NeighbourSets* sets, const DepthCompletionParams& params,
                     const GroundPlane& plane, double median_depth, ThreadPool& pool,
                     PixelPredictions& out, const cv::Mat& image = cv::Mat());

/// `ground_gp` on dense input (ground_gp_model.cpp): the prior is the edge-aware interpolation of
/// inverse depth on the Delaunay triangulation of the samples; no residual GP (the prior already
/// passes through every sample, so the GP's posterior mean would equal it). The samples are those
/// of `triangulation` (the caller may have started it early; with hidden returns dropped, the
/// visible ones). Work buffers in `scratch`. `image` (may be empty): the camera image, for the
/// occlusion vote's colours (ground.dense_vote_colour_sigma > 0).
void predictGroundGpDense(const PixelAngleGrid& angles, const DepthCompletionParams& params,
                          const GroundPlane& plane, double median_depth, ThreadPool& pool,
                          PixelPredictions& out, ModelScratch& scratch,
                          BackgroundTriangulation& triangulation, const cv::Mat& image = cv::Mat());

/// Mean angular spacing of the samples in the camera's view, sqrt(view area / samples in view), in
/// degrees; infinity when none is in view.
double meanSampleSpacingDeg(const std::vector<AngularSample>& samples,
                            const PixelAngleGrid& angles);

/// The dense mode's edge ratio for these samples: ground.dense_edge_ratio, or
/// ground.dense_edge_ratio_per_deg times meanSampleSpacingDeg when that is larger (none in view:
/// dense_edge_ratio).
double denseEdgeRatio(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                      const GroundPriorParams& ground);

/// Whether `ground_gp` runs its dense-input mode: params.ground.input, or for auto whether
/// meanSampleSpacingDeg is at most half of params.radius_deg.
bool groundInputIsDense(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                        const DepthCompletionParams& params);

}  // namespace multimodal_nvs
