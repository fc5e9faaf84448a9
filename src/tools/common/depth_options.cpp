#include "depth_options.hpp"

#include "multimodal_nvs/core/depth/ground_prior.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"

namespace multimodal_nvs {
namespace cli {

void declareDepthModelOptions(Args& args) {
  args.option("model", 1,
              "local_gp_mle|kernel|ground_gp|image_guided|nearest|linear|ipbasic|constant",
              "local_gp_mle");
  args.option("radius-deg", 1, "neighbourhood radius in degrees", "2");
  args.option("amplitude", 1, "GP amplitude a (kernel variance a^2)", "25");
  args.option("noise", 1, "GP observation noise sigma", "0.5");
  args.option("length-scale-min", 1, "length-scale search lower bound (deg)", "0.1");
  args.option("length-scale-max", 1, "length-scale search upper bound (deg)", "10");
  args.option("opt-tol", 1, "golden-section tolerance", "0.001");
  args.option("opt-max-iter", 1, "golden-section iterations at most", "64");
  args.option("kernel-length-scale-deg", 1, "kernel-regression length scale", "0.75");
  args.option("shift", 1, "auto|median|mean|none|<metres>", "median");
  args.option("var-threshold", 1, "predictions with larger variance are invalid", "inf");
  args.option("threads", 1, "worker threads (0: all cores)", "0");
  args.option("max-neighbors", 1, "0: exact; K>0: tile approximation with at most K samples", "0");
  args.option("approx-tile", 1, "tile side (grid pixels) of the approximation", "16");
  args.option("ground-pose", 1,
              "ground_gp: VoD pose file giving the camera's height and tilt "
              "(default with --vod-root: the frame's pose)");
  args.option("pose-key", 1, "key in the pose file", "odomToCamera");
  args.option("camera-height", 1, "ground_gp: camera height above the ground without a pose",
              "1.3");
  args.option("far-depth", 1, "ground_gp: prior depth without any support (0: median depth)", "0");
  args.option("residual-amplitude", 1, "ground_gp: GP amplitude of the residual (0: no GP)", "1");
  args.option("surface-k", 1, "ground_gp: nearest samples per pixel for the surface prior", "8");
  args.option("surface-rank", 1, "ground_gp: which smallest of their depths (1 = minimum)", "2");
  args.option("surface-step-px", 1, "ground_gp: lattice step of the surface prior (pixels)", "16");
  args.option("relative-sigma", 1, "ground_gp: prior std / depth at a sample", "0.25");
  args.option("relative-sigma-per-deg", 1, "ground_gp: growth of prior std / depth per degree",
              "0.10");
  args.option("ground-input", 1,
              "ground_gp: auto|sparse|dense (auto: dense when the samples in view are at most "
              "radius/2 apart on average)",
              "auto");
  args.option("dense-edge-ratio", 1,
              "ground_gp dense: relative depth step that separates two surfaces", "0.1");
  args.option("dense-relative-sigma", 1, "ground_gp dense: prior std / depth on a surface", "0.03");
  args.option("guided-lambda", 1, "image_guided: smoothness weight of the fast global smoother",
              "4000");
  args.option("guided-sigma-color", 1, "image_guided: image step (8-bit) that counts as an edge",
              "8");
  args.option("guided-iterations", 1, "image_guided: smoother iterations", "3");
  args.option("guided-prior-weight", 1, "image_guided: confidence of the prior per pixel", "0.001");
  args.option("guided-far-depth", 1, "image_guided: depth of the sky and above the horizon", "100");
  args.option("guided-ground-prior", 1, "image_guided: 1 ground-plane prior, 0 median depth", "1");
  args.option("guided-surface-prior", 1,
              "image_guided: 1 the prior is nearer of ground and nearest return, 0 ground only",
              "1");
  args.option("guided-edges", 1, "image_guided: 1 follow the image's edges, 0 ignore them", "1");
  args.option("guided-sky", 1, "image_guided: 1 send the detected sky to the far depth", "1");
  args.option("guided-sky-gradient", 1, "image_guided: image gradient that ends the sky", "12");
  args.option("guided-sky-brightness", 1, "image_guided: the sky is at least this bright (8-bit)",
              "120");
  args.option("guided-sky-sigma", 1, "image_guided: std (m) of the sky's depth", "1");
  args.option("guided-relative-sigma", 1, "image_guided: std / depth where only the prior speaks",
              "0.25");
  args.option("guided-return-relative-sigma", 1, "image_guided: std / depth at a return", "0.05");
  args.option("guided-splat-radius", 1, "image_guided: grid pixels a return covers around it", "0");
}

DepthCompletionParams depthModelParams(const Args& args) {
  DepthCompletionParams p;
  p.model = parseDepthModel(args.str("model", "local_gp_mle"));
  p.radius_deg = args.number("radius-deg", p.radius_deg);
  p.gp.amplitude = args.number("amplitude", p.gp.amplitude);
  p.gp.noise = args.number("noise", p.gp.noise);
  p.gp.length_scale_min = args.number("length-scale-min", p.gp.length_scale_min);
  p.gp.length_scale_max = args.number("length-scale-max", p.gp.length_scale_max);
  p.gp.tolerance = args.number("opt-tol", p.gp.tolerance);
  p.gp.max_iterations = args.integer("opt-max-iter", p.gp.max_iterations);
  p.kernel_length_scale_deg = args.number("kernel-length-scale-deg", p.kernel_length_scale_deg);
  p.shift = DepthShift::parse(args.str("shift", "median"));
  p.var_threshold = args.number("var-threshold", p.var_threshold);
  p.threads = args.integer("threads", 0);
  p.max_neighbors = args.integer("max-neighbors", 0);
  p.approx_tile = args.integer("approx-tile", p.approx_tile);
  GroundPriorParams& g = p.ground;
  g.camera_height = args.number("camera-height", g.camera_height);
  g.far_depth = args.number("far-depth", g.far_depth);
  g.residual_amplitude = args.number("residual-amplitude", g.residual_amplitude);
  g.surface_k = args.integer("surface-k", g.surface_k);
  g.surface_rank = args.integer("surface-rank", g.surface_rank);
  g.surface_step_px = args.integer("surface-step-px", g.surface_step_px);
  g.relative_sigma = args.number("relative-sigma", g.relative_sigma);
  g.relative_sigma_per_deg = args.number("relative-sigma-per-deg", g.relative_sigma_per_deg);
  g.input = parseGroundInput(args.str("ground-input", "auto"));
  g.dense_edge_ratio = args.number("dense-edge-ratio", g.dense_edge_ratio);
  g.dense_relative_sigma = args.number("dense-relative-sigma", g.dense_relative_sigma);
  ImageGuidedParams& ig = p.guided;
  ig.lambda = args.number("guided-lambda", ig.lambda);
  ig.sigma_color = args.number("guided-sigma-color", ig.sigma_color);
  ig.iterations = args.integer("guided-iterations", ig.iterations);
  ig.prior_weight = args.number("guided-prior-weight", ig.prior_weight);
  ig.far_depth = args.number("guided-far-depth", ig.far_depth);
  ig.ground_prior = args.integer("guided-ground-prior", ig.ground_prior) != 0;
  ig.surface_prior = args.integer("guided-surface-prior", ig.surface_prior) != 0;
  ig.edges = args.integer("guided-edges", ig.edges) != 0;
  ig.sky = args.integer("guided-sky", ig.sky) != 0;
  ig.sky_gradient = args.number("guided-sky-gradient", ig.sky_gradient);
  ig.sky_brightness = args.number("guided-sky-brightness", ig.sky_brightness);
  ig.sky_sigma = args.number("guided-sky-sigma", ig.sky_sigma);
  ig.relative_sigma = args.number("guided-relative-sigma", ig.relative_sigma);
  ig.return_relative_sigma = args.number("guided-return-relative-sigma", ig.return_relative_sigma);
  ig.splat_radius_px = args.integer("guided-splat-radius", ig.splat_radius_px);
  p.validate();
  return p;
}

void applyGroundPose(const Args& args, const std::string& default_pose, DepthCompletionParams& p) {
  if (p.model != DepthModel::kGroundGp && p.model != DepthModel::kImageGuided) return;
  std::string pose_path = args.str("ground-pose");
  if (pose_path.empty() && !default_pose.empty() && io::fileExists(default_pose)) {
    pose_path = default_pose;
  }
  if (pose_path.empty()) return;
  const GroundPlane plane = GroundPlane::fromCameraToWorld(
      io::readVodPose(pose_path, args.str("pose-key", "odomToCamera")));
  p.ground.up_x = plane.up.x();
  p.ground.up_y = plane.up.y();
  p.ground.up_z = plane.up.z();
  p.ground.camera_height = plane.height;
}

}  // namespace cli
}  // namespace multimodal_nvs
