#include "multimodal_nvs/ros/depth_completion_config.hpp"

#include <cmath>
#include <limits>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

DepthCompletionSettings settingsFromConfig(const DepthCompletionConfig& config) {
  DepthCompletionSettings settings;
  DepthCompletionParams& p = settings.params;
  p.model = parseDepthModel(config.model);
  p.radius_deg = config.radius_deg;
  p.gp.amplitude = config.amplitude;
  p.gp.noise = config.noise;
  p.gp.length_scale_min = config.length_scale_min;
  p.gp.length_scale_max = config.length_scale_max;
  p.gp.tolerance = config.tolerance;
  p.gp.max_iterations = config.max_iterations;
  p.kernel_length_scale_deg = config.kernel_length_scale_deg;
  p.shift = DepthShift::parse(config.shift);
  p.retain_percent = config.retain_percent;
  // dynamic_reconfigure cannot carry infinity, so 0 stands for "no threshold".
  p.var_threshold =
      config.var_threshold > 0.0 ? config.var_threshold : std::numeric_limits<double>::infinity();
  p.max_neighbors = config.max_neighbors;
  p.approx_tile = config.approx_tile;
  p.threads = config.threads;
  p.ground.camera_height = config.ground_camera_height;
  p.ground.setPitchDeg(config.ground_pitch_deg);
  p.ground.far_depth = config.ground_far_depth;
  p.ground.surface_k = config.ground_surface_k;
  p.ground.surface_rank = config.ground_surface_rank;
  p.ground.surface_step_px = config.ground_surface_step_px;
  p.ground.surface_colour_sigma = config.ground_surface_colour_sigma;
  p.ground.surface_colour_walls = config.ground_surface_colour_walls;
  p.ground.surface_colour_fill_deg = config.ground_surface_colour_fill_deg;
  p.ground.residual_amplitude = config.ground_residual_amplitude;
  p.ground.relative_sigma = config.ground_relative_sigma;
  p.ground.relative_sigma_per_deg = config.ground_relative_sigma_per_deg;
  p.ground.input = parseGroundInput(config.ground_input);
  p.ground.dense_edge_ratio = config.ground_dense_edge_ratio;
  p.ground.dense_edge_ratio_per_deg = config.ground_dense_edge_ratio_per_deg;
  p.ground.dense_relative_sigma = config.ground_dense_relative_sigma;
  p.ground.dense_vote_colour_sigma = config.ground_dense_vote_colour_sigma;
  p.ground.dense_vote_colour_px = config.ground_dense_vote_colour_px;
  p.ground.image_sky = config.ground_image_sky;
  p.ground.drop_hidden_returns = config.ground_drop_hidden_returns;
  ImageGuidedParams& g = p.guided;
  g.lambda = config.guided_lambda;
  g.sigma_color = config.guided_sigma_color;
  g.iterations = config.guided_iterations;
  g.smooth_scale = config.guided_smooth_scale;
  g.prior_step_px = config.guided_prior_step_px;
  g.prior_colour_sigma = config.guided_prior_colour_sigma;
  g.prior_colour_walls = config.guided_prior_colour_walls;
  g.prior_colour_fill_deg = config.guided_prior_colour_fill_deg;
  g.prior_weight = config.guided_prior_weight;
  g.prior_reference_density = config.guided_prior_reference_density;
  g.prior_weight_above_returns = config.guided_prior_weight_above_returns;
  g.far_depth = config.guided_far_depth;
  g.ground_prior = config.guided_ground_prior;
  g.surface_prior = config.guided_surface_prior;
  g.lateral_prior = config.guided_lateral_prior;
  g.ground_gp_prior = config.guided_ground_gp_prior;
  g.edges = config.guided_edges;
  g.sky = config.guided_sky;
  g.sky_gradient = config.guided_sky_gradient;
  g.sky_brightness = config.guided_sky_brightness;
  g.sky_max_warmth = config.guided_sky_max_warmth;
  g.sky_sigma = config.guided_sky_sigma;
  g.relative_sigma = config.guided_relative_sigma;
  g.return_relative_sigma = config.guided_return_relative_sigma;
  g.splat_radius_px = config.guided_splat_radius_px;
  p.validate();
  if (config.stride < 1) throw InputError("parameter stride must be >= 1");
  if (config.cloud_stride < 1) throw InputError("parameter cloud_stride must be >= 1");
  settings.stride = config.stride;
  settings.cloud_stride = config.cloud_stride;
  return settings;
}

void writeSettingsToConfig(const DepthCompletionSettings& settings, DepthCompletionConfig& config) {
  const DepthCompletionParams& p = settings.params;
  config.model = toString(p.model);
  config.radius_deg = p.radius_deg;
  config.amplitude = p.gp.amplitude;
  config.noise = p.gp.noise;
  config.length_scale_min = p.gp.length_scale_min;
  config.length_scale_max = p.gp.length_scale_max;
  config.tolerance = p.gp.tolerance;
  config.max_iterations = p.gp.max_iterations;
  config.kernel_length_scale_deg = p.kernel_length_scale_deg;
  config.shift = p.shift.toString();
  config.retain_percent = p.retain_percent;
  config.var_threshold = std::isfinite(p.var_threshold) ? p.var_threshold : 0.0;
  config.max_neighbors = p.max_neighbors;
  config.approx_tile = p.approx_tile;
  config.threads = p.threads;
  config.ground_camera_height = p.ground.camera_height;
  config.ground_pitch_deg = p.ground.pitchDeg();
  config.ground_far_depth = p.ground.far_depth;
  config.ground_surface_k = p.ground.surface_k;
  config.ground_surface_rank = p.ground.surface_rank;
  config.ground_surface_step_px = p.ground.surface_step_px;
  config.ground_surface_colour_sigma = p.ground.surface_colour_sigma;
  config.ground_surface_colour_walls = p.ground.surface_colour_walls;
  config.ground_surface_colour_fill_deg = p.ground.surface_colour_fill_deg;
  config.ground_residual_amplitude = p.ground.residual_amplitude;
  config.ground_relative_sigma = p.ground.relative_sigma;
  config.ground_relative_sigma_per_deg = p.ground.relative_sigma_per_deg;
  config.ground_input = toString(p.ground.input);
  config.ground_dense_edge_ratio = p.ground.dense_edge_ratio;
  config.ground_dense_edge_ratio_per_deg = p.ground.dense_edge_ratio_per_deg;
  config.ground_dense_relative_sigma = p.ground.dense_relative_sigma;
  config.ground_dense_vote_colour_sigma = p.ground.dense_vote_colour_sigma;
  config.ground_dense_vote_colour_px = p.ground.dense_vote_colour_px;
  config.ground_image_sky = p.ground.image_sky;
  config.ground_drop_hidden_returns = p.ground.drop_hidden_returns;
  const ImageGuidedParams& g = p.guided;
  config.guided_lambda = g.lambda;
  config.guided_sigma_color = g.sigma_color;
  config.guided_iterations = g.iterations;
  config.guided_smooth_scale = g.smooth_scale;
  config.guided_prior_step_px = g.prior_step_px;
  config.guided_prior_colour_sigma = g.prior_colour_sigma;
  config.guided_prior_colour_walls = g.prior_colour_walls;
  config.guided_prior_colour_fill_deg = g.prior_colour_fill_deg;
  config.guided_prior_weight = g.prior_weight;
  config.guided_prior_reference_density = g.prior_reference_density;
  config.guided_prior_weight_above_returns = g.prior_weight_above_returns;
  config.guided_far_depth = g.far_depth;
  config.guided_ground_prior = g.ground_prior;
  config.guided_surface_prior = g.surface_prior;
  config.guided_lateral_prior = g.lateral_prior;
  config.guided_ground_gp_prior = g.ground_gp_prior;
  config.guided_edges = g.edges;
  config.guided_sky = g.sky;
  config.guided_sky_gradient = g.sky_gradient;
  config.guided_sky_brightness = g.sky_brightness;
  config.guided_sky_max_warmth = g.sky_max_warmth;
  config.guided_sky_sigma = g.sky_sigma;
  config.guided_relative_sigma = g.relative_sigma;
  config.guided_return_relative_sigma = g.return_relative_sigma;
  config.guided_splat_radius_px = g.splat_radius_px;
  config.stride = settings.stride;
  config.cloud_stride = settings.cloud_stride;
}

}  // namespace multimodal_nvs
