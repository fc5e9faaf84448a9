#include "multimodal_nvs/core/depth/models/model_registry.hpp"

#include <algorithm>
#include <memory>

#include "multimodal_nvs/core/depth/depth_shift.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/depth/models/constant_model.hpp"
#include "multimodal_nvs/core/depth/models/ground_gp_model.hpp"
#include "multimodal_nvs/core/depth/models/image_guided_model.hpp"
#include "multimodal_nvs/core/depth/models/ipbasic_model.hpp"
#include "multimodal_nvs/core/depth/models/kernel_model.hpp"
#include "multimodal_nvs/core/depth/models/linear_model.hpp"
#include "multimodal_nvs/core/depth/models/local_gp_model.hpp"
#include "multimodal_nvs/core/depth/models/nearest_model.hpp"
#include "multimodal_nvs/core/depth/models/prediction_upsampling.hpp"
#include "multimodal_nvs/core/depth/models/tiled_local_gp_model.hpp"
#include "multimodal_nvs/core/depth/neighbour_sets.hpp"

namespace multimodal_nvs {
namespace {
/// A model that needs no neighbour sets (the baselines), or nullptr for the GP models.
using BaselineModel = void (*)(const std::vector<AngularSample>&, const PixelAngleGrid&,
                               const DepthCompletionParams&, ThreadPool&, PixelPredictions&);

BaselineModel baselineModel(DepthModel model) {
  switch (model) {
    case DepthModel::kNearest:
      return predictNearest;
    case DepthModel::kLinear:
      return predictLinear;
    case DepthModel::kIpBasic:
      return predictIpBasic;
    case DepthModel::kConstant:
      return predictConstant;
    case DepthModel::kLocalGpMle:
    case DepthModel::kKernel:
    case DepthModel::kGroundGp:
    case DepthModel::kImageGuided:
      break;
  }
  return nullptr;
}

/// The median depth of the samples (ground_gp's far value): the shift itself when that is the
/// median (the default), so the samples are not sorted twice per frame.
double medianDepth(const std::vector<AngularSample>& samples, const DepthCompletionParams& params,
                   double shift) {
  return params.shift.mode == DepthShift::Mode::kMedian ? shift
                                                        : computeShift(DepthShift{}, samples);
}

}  // namespace

bool groundGpUsesTiles(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                       const DepthCompletionParams& params) {
  if (params.max_neighbors > 0) return true;
  return meanSamplesWithinRadius(samples, angles, params) > kLargeNeighbourSetMean;
}

bool isBaseline(DepthModel model) {
  return baselineModel(model) != nullptr;
}

namespace {

/// ground_gp once its ground is chosen: dense input interpolates its triangles, large neighbour
/// sets take the tile approximation, the rest the exact sets. Returns the number of sets.
int predictGroundGpModel(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                         const DepthCompletionParams& params, const GroundChoice& choice,
                         double shift, ThreadPool& pool, PixelPredictions& out,
                         GroundChoice* ground, ModelScratch* scratch,
                         BackgroundTriangulation& triangulation, const cv::Mat& image) {
  // The colours only where a return's pixel is where it was seen.
  const cv::Mat& colours = choice.single_scan_plane ? cv::Mat() : image;
  if (choice.dense) {
    // Dense input needs no neighbour sets: the interpolating prior is the prediction.
    ModelScratch local;
    predictGroundGpDense(angles, params, choice.plane, medianDepth(samples, params, shift), pool,
                         out, scratch != nullptr ? *scratch : local, triangulation, colours);
    if (ground) {
      ground->hidden_returns = triangulation.hiddenCount();
      ground->edge_ratio = params.ground.dense_edge_ratio;
    }
    return 0;
  }
  if (groundGpUsesTiles(samples, angles, params)) {
    // No neighbour sets: building them alone takes longer than the whole approximation.
    if (ground) ground->tiled_residual = true;
    DepthCompletionParams tiled = params;
    if (tiled.max_neighbors == 0) tiled.max_neighbors = kAutoMaxNeighbors;
    predictGroundGp(samples, angles, nullptr, tiled, choice.plane,
                    medianDepth(samples, params, shift), pool, out, colours);
    return 0;
  }
  const NeighbourSets sets =
      NeighbourSets::build(samples, angles, static_cast<float>(params.radius_deg), pool);
  predictGroundGp(samples, angles, &sets, params, choice.plane, medianDepth(samples, params, shift),
                  pool, out, colours);
  return sets.setCount();
}

}  // namespace

int predictWithModel(const std::vector<AngularSample>& samples, const PixelAngleGrid& angles,
                     const DepthCompletionParams& requested, double shift, ThreadPool& pool,
                     PixelPredictions& out, const cv::Mat& image, GroundChoice* ground,
                     ModelScratch* scratch, ImageGuidedReport* guided) {
  // ground_gp's dense mode separates surfaces at a depth step that grows with the returns' spacing
  // (denseEdgeRatio, which also knows when that is switched off): decided once per scan, before the
  // hidden-return filter below uses it too.
  DepthCompletionParams with_edge_ratio;
  const DepthCompletionParams* chosen = &requested;
  if (requested.model == DepthModel::kGroundGp) {
    with_edge_ratio = requested;
    with_edge_ratio.ground.dense_edge_ratio = denseEdgeRatio(samples, angles, requested.ground);
    chosen = &with_edge_ratio;
  }
  const DepthCompletionParams& params = *chosen;
  if (const BaselineModel baseline = baselineModel(params.model)) {
    baseline(samples, angles, params, pool, out);
    return 0;
  }
  // ground_gp on LiDAR triangulates its returns: the serial triangulation starts now, on its own
  // thread, and overlaps the ground plane's fit. Only when dense input is asked for: in the auto
  // mode the fit decides, and a radar scan would not need the triangles. (image_guided never
  // needs them: on dense input it does not run ground_gp, see below.)
  using Input = GroundPriorParams::Input;
  // In the dense mode it triangulates the returns the camera can see, when the scan's origin is
  // known (the filter runs on the triangulation's thread, before it).
  const GroundPriorParams& g = params.ground;
  BackgroundTriangulation triangulation(
      samples, angles,
      params.model == DepthModel::kGroundGp && g.input == Input::kDense && pool.size() > 1,
      params.model == DepthModel::kGroundGp && g.drop_hidden_returns && g.scan_origin_known,
      1.0 + g.dense_edge_ratio, Eigen::Vector3d(g.scan_origin_x, g.scan_origin_y, g.scan_origin_z),
      params.model == DepthModel::kGroundGp);
  // Both models that stand on the ground take its plane (and ground_gp its mode) from the returns
  // when they allow it, else from the pose or the parameters.
  GroundChoice choice;
  if (params.model == DepthModel::kGroundGp || params.model == DepthModel::kImageGuided) {
    choice = chooseGround(samples, angles, params);
    if (ground) *ground = choice;
  }
  if (params.model == DepthModel::kGroundGp) {
    // The image's sky does not depend on the prediction: found first, while the triangulation
    // (dense input) still runs on its thread, it fills the core that would wait for the triangles.
    std::vector<std::uint8_t> sky;
    if (params.ground.image_sky && !image.empty())
      sky = imageSkyMask(samples, angles, params.guided, choice.plane, image, pool);
    const int sets = predictGroundGpModel(samples, angles, params, choice, shift, pool, out, ground,
                                          scratch, triangulation, image);
    if (!sky.empty()) applySkyMask(sky, params.guided, out);
    return sets;
  }
  if (params.model == DepthModel::kImageGuided) {
    ImageGuidedReport unused_report;
    ImageGuidedReport& report = guided != nullptr ? *guided : unused_report;
    // On sparse input (ground_gp's sparse mode: radar) ground_gp's prediction is the prior the
    // smoother spreads the returns over: a few hundred returns leave most surfaces to the prior,
    // and on real frames ground_gp's is the better one (radar MAE against the LiDAR: VoD 3.33
    // against 4.98 m with the model's own prior, Astyx 5.02 against 6.06, nuScenes 6.22 against
    // 7.54), although the synthetic street's frames favour the own prior. Dense input (LiDAR)
    // carries its surfaces itself; there ground_gp's interpolated triangles as the prior lost
    // 1.8 dB (synthetic dev, covered PSNR), so it keeps the ground and nearest-surface prior.
    if (!params.guided.ground_gp_prior || choice.dense) {
      report = predictImageGuided(samples, angles, params, choice, image, pool, out);
      return 0;
    }
    // ground_gp first, on the same ground, then its prediction as the prior.
    DepthCompletionParams ground_gp = params;
    ground_gp.model = DepthModel::kGroundGp;
    ground_gp.ground.surface_colour_sigma = params.guided.prior_colour_sigma;
    ground_gp.ground.surface_colour_walls = params.guided.prior_colour_walls;
    ground_gp.ground.surface_colour_fill_deg = params.guided.prior_colour_fill_deg;
    PixelPredictions own_prior;
    PixelPredictions& prior = scratch != nullptr ? scratch->model_prior : own_prior;
    // The prior is computed on a coarser grid when prior_step_px asks for it (only with the
    // completer's scratch, which keeps that grid's angles between frames) and interpolated as
    // image_guided reads it.
    const StrideGrid& grid = angles.grid();
    const int factor =
        scratch != nullptr ? std::max(1, params.guided.prior_step_px / grid.stride) : 1;
    if (factor > 1) {
      const StrideGrid coarse{grid.image, grid.stride * factor};
      if (!scratch->prior_angles || !scratch->prior_angles->matches(angles.intrinsics(), coarse)) {
        scratch->prior_angles = std::make_unique<PixelAngleGrid>(angles.intrinsics(), coarse);
      }
      const int sets =
          predictGroundGpModel(samples, *scratch->prior_angles, ground_gp, choice, shift, pool,
                               scratch->coarse_prior, ground, scratch, triangulation, image);
      scratch->upsampled_prior.prepare(scratch->coarse_prior, coarse, grid, factor, pool);
      const PredictionRows prior_rows(scratch->upsampled_prior);
      report = predictImageGuided(samples, angles, params, choice, image, pool, out, &prior_rows);
      return sets;
    }
    const int sets = predictGroundGpModel(samples, angles, ground_gp, choice, shift, pool, prior,
                                          ground, scratch, triangulation, image);
    const PredictionRows prior_rows(prior, grid.rows(), grid.cols());
    report = predictImageGuided(samples, angles, params, choice, image, pool, out, &prior_rows);
    return sets;
  }
  if (params.model == DepthModel::kLocalGpMle && params.max_neighbors > 0) {
    return predictTiledLocalGp(samples, angles, params, shift, pool, out);
  }
  const NeighbourSets sets =
      NeighbourSets::build(samples, angles, static_cast<float>(params.radius_deg), pool);
  if (params.model == DepthModel::kLocalGpMle) {
    predictLocalGp(samples, angles, sets, params, shift, pool, out);
  } else {
    predictKernel(samples, angles, sets, params, shift, pool, out);
  }
  return sets.setCount();
}

}  // namespace multimodal_nvs
