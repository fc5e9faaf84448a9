#include "depth_options.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace multimodal_nvs {
namespace cli {

void declareDepthModelOptions(CLI::App& app, DepthModelOptions& o) {
  DepthCompletionParams& p = o.params;
  app.add_option("--model", o.model,
                 "local_gp_mle|kernel|ground_gp|image_guided|nearest|linear|ipbasic|constant")
      ->group(kModel);
  app.add_option("--radius-deg", p.radius_deg, "neighbourhood radius in degrees")
      ->check(positive())
      ->group(kModel);
  app.add_option("--amplitude", p.gp.amplitude, "GP amplitude a (kernel variance a^2)")
      ->check(positive())
      ->group(kModel);
  app.add_option("--noise", p.gp.noise, "GP observation noise sigma")
      ->check(finite())
      ->group(kModel);
  app.add_option("--length-scale-min", p.gp.length_scale_min,
                 "length-scale search lower bound (deg)")
      ->check(positive())
      ->group(kModel);
  app.add_option("--length-scale-max", p.gp.length_scale_max,
                 "length-scale search upper bound (deg)")
      ->check(positive())
      ->group(kModel);
  app.add_option("--opt-tol", p.gp.tolerance, "golden-section tolerance")
      ->check(positive())
      ->group(kModel);
  app.add_option("--opt-max-iter", p.gp.max_iterations, "golden-section iterations at most")
      ->check(atLeast(1))
      ->group(kModel);
  app.add_option("--kernel-length-scale-deg", p.kernel_length_scale_deg,
                 "kernel-regression length scale")
      ->check(positive())
      ->group(kModel);
  app.add_option("--shift", o.shift, "auto|median|mean|none|<metres>")->group(kModel);
  app.add_option("--var-threshold", p.var_threshold, "predictions with larger variance are invalid")
      ->group(kModel);
  app.add_option("--threads", p.threads, "worker threads (0: all cores)")
      ->check(atLeast(0))
      ->group(kModel);
  app.add_option("--max-neighbors", p.max_neighbors,
                 "0: exact (ground_gp: exact unless neighbour sets are large); K>0: tile "
                 "approximation with at most K samples")
      ->check(atLeast(0))
      ->group(kModel);
  app.add_option("--approx-tile", p.approx_tile, "tile side (grid pixels) of the approximation")
      ->check(atLeast(1))
      ->group(kModel);

  GroundPriorParams& g = p.ground;
  app.add_option("--ground-pose", o.ground_pose,
                 "VoD pose file giving the camera's height and tilt (default with --vod-root: the "
                 "frame's pose when it exists; without a pose: --camera-height and "
                 "--camera-pitch-deg)")
      ->group(kGround);
  declarePoseKeyOption(app, o.pose_key, kGround, "that places the camera above the road");
  app.add_option("--camera-height", g.camera_height,
                 "camera height above the ground without a pose")
      ->check(positive())
      ->group(kGround);
  app.add_option("--camera-pitch-deg", o.camera_pitch_deg,
                 "the optical axis's angle above the road without a pose (degrees, positive: "
                 "looking up; the node's ground_pitch_deg)")
      ->check(CLI::Range(-45.0, 45.0))
      ->group(kGround);
  app.add_option("--far-depth", g.far_depth, "prior depth without any support (0: median depth)")
      ->check(atLeast(0))
      ->group(kGround);
  app.add_option("--residual-amplitude", g.residual_amplitude,
                 "GP amplitude of the residual (0: no GP)")
      ->check(atLeast(0))
      ->group(kGround);
  app.add_option("--surface-k", g.surface_k, "nearest samples per pixel for the surface prior")
      ->check(atLeast(1))
      ->group(kGround);
  app.add_option("--surface-rank", g.surface_rank, "which smallest of their depths (1 = minimum)")
      ->check(atLeast(1))
      ->group(kGround);
  app.add_option("--surface-step-px", g.surface_step_px,
                 "lattice step of the surface prior (pixels)")
      ->check(atLeast(1))
      ->group(kGround);
  app.add_option("--surface-colour-sigma", g.surface_colour_sigma,
                 "surface prior: weigh the samples by the colour of their pixel against the "
                 "pixel's (Gaussian of this distance, 0..255 per channel; 0: off)")
      ->check(atLeast(0))
      ->group(kGround);
  app.add_option("--surface-colour-walls", g.surface_colour_walls,
                 "with --surface-colour-sigma: a return that looks like the pixel continues as a "
                 "wall along the view towards the image centre")
      ->group(kGround);
  app.add_option("--surface-colour-fill-deg", g.surface_colour_fill_deg,
                 "with --surface-colour-sigma: a node that looks like none of its returns takes "
                 "the look-alike return of the nearest node along its row or column within this "
                 "angle (degrees) that found one (0: off)")
      ->check(CLI::Range(0.0, 90.0))
      ->group(kGround);
  app.add_option("--relative-sigma", g.relative_sigma, "prior std / depth at a sample")
      ->check(atLeast(0))
      ->group(kGround);
  app.add_option("--relative-sigma-per-deg", g.relative_sigma_per_deg,
                 "growth of prior std / depth per degree")
      ->check(atLeast(0))
      ->group(kGround);
  app.add_option("--ground-input", o.ground_input,
                 "auto|sparse|dense (auto: dense when the samples in view are at most radius/2 "
                 "apart on average)")
      ->group(kGround);
  app.add_option("--dense-edge-ratio", g.dense_edge_ratio,
                 "dense input: relative depth step that separates two surfaces")
      ->check(positive())
      ->group(kGround);
  app.add_option("--dense-edge-ratio-per-deg", g.dense_edge_ratio_per_deg,
                 "dense input: the edge ratio is at least this times the returns' mean angular "
                 "spacing in view (degrees; sparse rings); 0: --dense-edge-ratio alone")
      ->check(CLI::Range(0.0, 10.0))
      ->group(kGround);
  app.add_option("--dense-relative-sigma", g.dense_relative_sigma,
                 "dense input: prior std / depth on a surface")
      ->check(positive())
      ->group(kGround);
  app.add_option("--dense-vote-colour-sigma", g.dense_vote_colour_sigma,
                 "dense input with the image: colour distance (0..255 per channel) at which a "
                 "return's vote at an occlusion edge falls to exp(-1/2) (0: by angle alone)")
      ->check(CLI::Range(0.0, 1000.0))
      ->group(kGround);
  app.add_option("--dense-vote-colour-px", g.dense_vote_colour_px,
                 "dense input with the image: distance (image pixels) from the nearest return at "
                 "which the colours get their full say in the vote (none within half of it)")
      ->check(CLI::Range(0.0, 10000.0))
      ->group(kGround);
  app.add_option("--drop-hidden-returns", g.drop_hidden_returns,
                 "dense input: 1 leave out the returns the camera cannot see (the scanner, at the "
                 "calibration's sensor origin, saw past a near object), 0 keep every return")
      ->group(kGround);
  app.add_option("--ground-image-sky", g.image_sky,
                 "1 the image's sky (the --guided-sky-* test) at the far clamp, 0 none")
      ->group(kGround);

  // image_guided (the depth model that follows the camera image). The on/off switches are for the
  // ablation of its ingredients.
  const char* guided = "image_guided";
  ImageGuidedParams& ig = p.guided;
  app.add_option("--guided-lambda", ig.lambda, "smoothness weight of the fast global smoother")
      ->check(positive())
      ->group(guided);
  app.add_option("--guided-sigma-color", ig.sigma_color,
                 "image step (8-bit) that counts as an edge")
      ->check(positive())
      ->group(guided);
  app.add_option("--guided-iterations", ig.iterations, "smoother iterations")
      ->check(atLeast(1))
      ->group(guided);
  app.add_option("--guided-smooth-scale", ig.smooth_scale,
                 "the smoother runs on a grid this many times coarser than the output")
      ->check(atLeast(1))
      ->group(guided);
  app.add_option("--guided-prior-step-px", ig.prior_step_px,
                 "image pixels between the samples of ground_gp's prior (interpolated between)")
      ->check(CLI::Range(1, 16))
      ->group(guided);
  app.add_option("--guided-prior-colour-sigma", ig.prior_colour_sigma,
                 "ground_gp's prior weighs its nearest returns by their pixel's colour against the "
                 "pixel's (Gaussian of this distance, 0..255 per channel; 0: off)")
      ->check(atLeast(0))
      ->group(guided);
  app.add_option("--guided-prior-colour-walls", ig.prior_colour_walls,
                 "ground_gp's prior continues a return that looks like the pixel as a wall along "
                 "the view towards the image centre (with the colours)")
      ->group(guided);
  app.add_option(
         "--guided-prior-colour-fill-deg", ig.prior_colour_fill_deg,
         "ground_gp's prior: a node that looks like none of its returns takes the look-alike "
         "return of the nearest node along its row or column within this angle (degrees) that "
         "found one (with the colours; 0: off)")
      ->check(CLI::Range(0.0, 90.0))
      ->group(guided);
  app.add_option("--guided-prior-weight", ig.prior_weight, "confidence of the prior per pixel")
      ->check(atLeast(0))
      ->group(guided);
  app.add_option("--guided-prior-reference-density", ig.prior_reference_density,
                 "returns per square degree of the view at which --guided-prior-weight holds; the "
                 "weight follows the frame's density in proportion (x0.25..x10; 0: fixed)")
      ->check(atLeast(0))
      ->group(guided);
  app.add_option("--guided-prior-weight-above-returns", ig.prior_weight_above_returns,
                 "with ground_gp's prior: the prior weighs this many times more above the "
                 "returns' band (all but the highest 2 % of them; 1: the same everywhere; not on a "
                 "2D scanner's single scan plane)")
      ->check(positive())
      ->group(guided);
  app.add_option("--guided-far-depth", ig.far_depth, "depth of the sky and above the horizon")
      ->check(positive())
      ->group(guided);
  app.add_option("--guided-ground-prior", ig.ground_prior, "1 ground-plane prior, 0 median depth")
      ->group(guided);
  app.add_option("--guided-surface-prior", ig.surface_prior,
                 "1 the prior is the nearer of ground and nearest return, 0 ground only")
      ->group(guided);
  app.add_option("--guided-lateral-prior", ig.lateral_prior,
                 "1 a nearest return continues as a wall along the view towards the centre")
      ->group(guided);
  app.add_option("--guided-ground-gp-prior", ig.ground_gp_prior,
                 "1 the prior is ground_gp's prediction, 0 the ground and nearest-surface prior")
      ->group(guided);
  app.add_option("--guided-edges", ig.edges, "1 follow the image's edges, 0 ignore them")
      ->group(guided);
  app.add_option("--guided-sky", ig.sky, "1 send the detected sky to the far depth")->group(guided);
  app.add_option("--guided-sky-gradient", ig.sky_gradient, "image gradient that ends the sky")
      ->check(atLeast(0))
      ->group(guided);
  app.add_option("--guided-sky-brightness", ig.sky_brightness,
                 "the sky is at least this bright (8-bit)")
      ->check(atLeast(0))
      ->group(guided);
  app.add_option("--guided-sky-max-warmth", ig.sky_max_warmth,
                 "the sky is at most this much redder than blue (8-bit; 255: no colour test)")
      ->group(guided);
  app.add_option("--guided-sky-sigma", ig.sky_sigma, "std (m) of the sky's depth")
      ->check(positive())
      ->group(guided);
  app.add_option("--guided-relative-sigma", ig.relative_sigma,
                 "std / depth where only the prior speaks")
      ->check(atLeast(0))
      ->group(guided);
  app.add_option("--guided-return-relative-sigma", ig.return_relative_sigma,
                 "std / depth at a return")
      ->check(atLeast(0))
      ->group(guided);
  app.add_option("--guided-splat-radius", ig.splat_radius_px,
                 "grid pixels a return covers around it")
      ->check(atLeast(0))
      ->group(guided);
}

DepthCompletionParams depthModelParams(const DepthModelOptions& o) {
  DepthCompletionParams p = o.params;
  // The parsers name the value; the message adds the option.
  auto named = [](const char* option, auto parse) {
    try {
      return parse();
    } catch (const InputError& e) {
      throw UsageError(std::string(option) + ": " + e.what());
    }
  };
  p.model = named("--model", [&] { return parseDepthModel(o.model); });
  p.shift = named("--shift", [&] { return DepthShift::parse(o.shift); });
  p.ground.input = named("--ground-input", [&] { return parseGroundInput(o.ground_input); });
  p.ground.setPitchDeg(o.camera_pitch_deg);  // a pose, applied afterwards, overrides it
  p.validate();
  return p;
}

void applyGroundPose(const DepthModelOptions& o, const std::string& default_pose,
                     DepthCompletionParams& p) {
  if (p.model != DepthModel::kGroundGp && p.model != DepthModel::kImageGuided) return;
  std::string pose_path = o.ground_pose;
  if (pose_path.empty() && !default_pose.empty() && io::fileExists(default_pose)) {
    pose_path = default_pose;
  }
  if (pose_path.empty()) return;
  std::ifstream in(pose_path, std::ios::binary);
  if (!in) throw InputError(pose_path + ": cannot open pose file (" + std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  // The pose is optional and its world need not be the odometry one: when the file lacks the key
  // asked for and the key is the default, any camera-to-world key serves for the ground's tilt
  // (applyCameraPose takes the height only when it is plausible for a road).
  std::string key = o.pose_key;
  const std::vector<std::string> keys = io::vodPoseKeys(text.str(), pose_path);
  if (std::find(keys.begin(), keys.end(), key) == keys.end() && key == io::odometryVodPoseKey()) {
    const auto map_key = std::find(keys.begin(), keys.end(), std::string("mapToCamera"));
    if (map_key != keys.end())
      key = *map_key;
    else if (!keys.empty())
      key = keys.front();
    else
      return;
  }
  applyCameraPose(io::parseVodPose(text.str(), key, pose_path), p.ground);
}

}  // namespace cli
}  // namespace multimodal_nvs
