#include "multimodal_nvs/core/depth/depth_params.hpp"

#include <cmath>
#include <cstdlib>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {

const char* toString(DepthModel model) {
  switch (model) {
    case DepthModel::kLocalGpMle:
      return "local_gp_mle";
    case DepthModel::kKernel:
      return "kernel";
    case DepthModel::kGroundGp:
      return "ground_gp";
    case DepthModel::kImageGuided:
      return "image_guided";
    case DepthModel::kNearest:
      return "nearest";
    case DepthModel::kLinear:
      return "linear";
    case DepthModel::kIpBasic:
      return "ipbasic";
    case DepthModel::kConstant:
      return "constant";
  }
  return "unknown";
}

DepthModel parseDepthModel(const std::string& name) {
  if (name == "local_gp_mle") return DepthModel::kLocalGpMle;
  if (name == "kernel") return DepthModel::kKernel;
  if (name == "ground_gp") return DepthModel::kGroundGp;
  if (name == "image_guided") return DepthModel::kImageGuided;
  if (name == "nearest") return DepthModel::kNearest;
  if (name == "linear") return DepthModel::kLinear;
  if (name == "ipbasic") return DepthModel::kIpBasic;
  if (name == "constant") return DepthModel::kConstant;
  throw InputError(
      "unknown depth model '" + name +
      "' (expected local_gp_mle, kernel, ground_gp, image_guided, nearest, linear, ipbasic or "
      "constant)");
}

const char* toString(GroundPriorParams::Input input) {
  switch (input) {
    case GroundPriorParams::Input::kAuto:
      return "auto";
    case GroundPriorParams::Input::kSparse:
      return "sparse";
    case GroundPriorParams::Input::kDense:
      return "dense";
  }
  return "unknown";
}

void GroundPriorParams::setPitchDeg(double pitch_deg) {
  const double pitch = pitch_deg * M_PI / 180.0;
  up_x = 0.0;
  up_y = -std::cos(pitch);
  up_z = std::sin(pitch);
}

double GroundPriorParams::pitchDeg() const {
  return std::atan2(up_z, -up_y) * 180.0 / M_PI;
}

GroundPriorParams::Input parseGroundInput(const std::string& name) {
  if (name == "auto") return GroundPriorParams::Input::kAuto;
  if (name == "sparse") return GroundPriorParams::Input::kSparse;
  if (name == "dense") return GroundPriorParams::Input::kDense;
  throw InputError("unknown ground_gp input '" + name + "' (expected auto, sparse or dense)");
}

DepthShift DepthShift::parse(const std::string& spec) {
  DepthShift s;
  if (spec == "auto" || spec == "median") return s;
  if (spec == "mean") {
    s.mode = Mode::kMean;
    return s;
  }
  if (spec == "none" || spec == "off" || spec == "0") {
    s.mode = Mode::kNone;
    return s;
  }
  char* end = nullptr;
  const double v = std::strtod(spec.c_str(), &end);
  if (spec.empty() || end != spec.c_str() + spec.size() || !std::isfinite(v)) {
    throw InputError("shift '" + spec + "' is not auto, median, mean, none or a finite number");
  }
  s.mode = Mode::kValue;
  s.value = v;
  return s;
}

std::string DepthShift::toString() const {
  switch (mode) {
    case Mode::kMedian:
      return "median";
    case Mode::kMean:
      return "mean";
    case Mode::kNone:
      return "none";
    case Mode::kValue:
      return std::to_string(value);
  }
  return "median";
}

void DepthCompletionParams::validate() const {
  auto fail = [](const std::string& what) { throw InputError("parameter " + what); };
  if (!(radius_deg > 0.0) || !std::isfinite(radius_deg)) fail("radius_deg must be > 0");
  if (model == DepthModel::kLocalGpMle) gp.validate();
  if (!(kernel_length_scale_deg > 0.0)) fail("kernel_length_scale_deg must be > 0");
  if (!(retain_percent >= 0.0 && retain_percent <= 100.0))
    fail("retain_percent must be in [0, 100]");
  if (std::isnan(var_threshold)) fail("var_threshold must not be NaN");
  if (max_neighbors < 0) fail("max_neighbors must be >= 0");
  if (model == DepthModel::kGroundGp) {
    if (ground.residual_amplitude > 0.0) gp.validate();
    if (!(ground.camera_height > 0.0)) fail("ground camera_height must be > 0");
    if (!(std::abs(ground.up_x) + std::abs(ground.up_y) + std::abs(ground.up_z) > 0.0)) {
      fail("ground up direction must not be zero");
    }
    if (ground.surface_k < 1 || ground.surface_rank < 1 || ground.surface_rank > ground.surface_k) {
      fail("ground surface_k >= 1 and 1 <= surface_rank <= surface_k");
    }
    if (ground.surface_step_px < 1) fail("ground surface_step_px must be >= 1");
    if (!(ground.surface_colour_sigma >= 0.0) || !std::isfinite(ground.surface_colour_sigma)) {
      fail("ground surface_colour_sigma must be >= 0");
    }
    if (!(ground.surface_colour_fill_deg >= 0.0) || !(ground.surface_colour_fill_deg <= 90.0)) {
      fail("ground surface_colour_fill_deg must be in [0, 90]");
    }
    if (ground.scan_origin_known &&
        !(std::isfinite(ground.scan_origin_x) && std::isfinite(ground.scan_origin_y) &&
          std::isfinite(ground.scan_origin_z))) {
      fail("ground scan_origin must be finite");
    }
    if (!(ground.dense_edge_ratio > 0.0) || !(ground.dense_relative_sigma >= 0.0)) {
      fail("ground dense_edge_ratio must be > 0 and dense_relative_sigma >= 0");
    }
    if (!(ground.dense_edge_ratio_per_deg >= 0.0) || !(ground.dense_edge_ratio_per_deg <= 10.0)) {
      fail("ground dense_edge_ratio_per_deg must be in [0, 10]");
    }
    if (!(ground.dense_vote_colour_sigma >= 0.0) || !(ground.dense_vote_colour_sigma <= 1000.0) ||
        !(ground.dense_vote_colour_px >= 0.0) || !(ground.dense_vote_colour_px <= 10000.0)) {
      fail(
          "ground dense_vote_colour_sigma must be in [0, 1000] and dense_vote_colour_px in [0, "
          "10000]");
    }
    if (!(ground.plane_distance > 0.0) || !(ground.precise_fraction >= 0.0) ||
        !(ground.precise_fraction <= 1.0)) {
      fail("ground plane_distance must be > 0 and precise_fraction in [0, 1]");
    }
    if (!(ground.residual_amplitude >= 0.0) || !(ground.relative_sigma >= 0.0) ||
        !(ground.relative_sigma_per_deg >= 0.0) || !(ground.far_depth >= 0.0)) {
      fail("ground residual_amplitude, relative sigmas and far_depth must be >= 0");
    }
  }
  if (model == DepthModel::kImageGuided) guided.validate(ground);
  if (approx_tile < 1) fail("approx_tile must be >= 1");
}

void ImageGuidedParams::validate(const GroundPriorParams& plane) const {
  auto fail = [](const std::string& what) { throw InputError("parameter image_guided " + what); };
  const double positive[] = {lambda, sigma_color, prior_weight, far_depth};
  for (double v : positive) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      fail("lambda, sigma_color, prior_weight and far_depth must be finite and > 0");
    }
  }
  if (!(prior_reference_density >= 0.0) || !std::isfinite(prior_reference_density)) {
    fail("prior_reference_density must be finite and >= 0");
  }
  if (!(prior_weight_above_returns > 0.0) || !std::isfinite(prior_weight_above_returns)) {
    fail("prior_weight_above_returns must be finite and > 0");
  }
  if (std::isnan(sky_max_warmth)) fail("sky_max_warmth must be a number");
  const double non_negative[] = {sky_gradient, sky_brightness, sky_sigma, relative_sigma,
                                 return_relative_sigma};
  for (double v : non_negative) {
    if (!(v >= 0.0) || !std::isfinite(v))
      fail("sky_gradient, sky_brightness and the sigmas must be >= 0");
  }
  if (iterations < 1 || iterations > 32) fail("iterations must be in [1, 32]");
  if (splat_radius_px < 0 || splat_radius_px > 16) fail("splat_radius_px must be in [0, 16]");
  if (smooth_scale < 1 || smooth_scale > 8) fail("smooth_scale must be in [1, 8]");
  if (prior_step_px < 1 || prior_step_px > 16) fail("prior_step_px must be in [1, 16]");
  if (!(prior_colour_sigma >= 0.0) || !std::isfinite(prior_colour_sigma)) {
    fail("prior_colour_sigma must be >= 0");
  }
  if (!(prior_colour_fill_deg >= 0.0) || !(prior_colour_fill_deg <= 90.0)) {
    fail("prior_colour_fill_deg must be in [0, 90]");
  }
  if (ground_prior) {
    if (!(plane.camera_height > 0.0)) fail("needs ground camera_height > 0");
    if (!(std::abs(plane.up_x) + std::abs(plane.up_y) + std::abs(plane.up_z) > 0.0)) {
      fail("needs a non-zero ground up direction");
    }
  }
}

}  // namespace multimodal_nvs
