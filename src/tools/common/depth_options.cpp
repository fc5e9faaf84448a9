#include "depth_options.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/depth/ground_plane_estimate.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"
#include "multimodal_nvs/core/io/vod_pose.hpp"

namespace multimodal_nvs {
namespace cli {

void declareDepthModelOptions(Args& args) {
  args.option("model", 1, "local_gp_mle|kernel|ground_gp|nearest|linear|ipbasic|constant",
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
  args.option("pose-key", 1,
              "key in the pose file (default: odomToCamera, else mapToCamera, else the first)");
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
  p.validate();
  return p;
}

void applyGroundPose(const Args& args, const std::string& default_pose, DepthCompletionParams& p) {
  if (p.model != DepthModel::kGroundGp) return;
  std::string pose_path = args.str("ground-pose");
  if (pose_path.empty() && !default_pose.empty() && io::fileExists(default_pose)) {
    pose_path = default_pose;
  }
  if (pose_path.empty()) return;
  std::ifstream in(pose_path, std::ios::binary);
  if (!in) throw InputError(pose_path + ": cannot open pose file");
  std::ostringstream text;
  text << in.rdbuf();
  std::string key = args.str("pose-key");
  if (key.empty()) {  // the pose is optional: any camera-to-world key serves for the ground
    const std::vector<std::string> keys = io::vodPoseKeys(text.str(), pose_path);
    for (const char* preferred : {"odomToCamera", "mapToCamera"}) {
      if (key.empty() && std::find(keys.begin(), keys.end(), preferred) != keys.end()) {
        key = preferred;
      }
    }
    if (key.empty() && !keys.empty()) key = keys.front();
    if (key.empty()) return;
  }
  applyCameraPose(io::parseVodPose(text.str(), key, pose_path), p.ground);
}

}  // namespace cli
}  // namespace multimodal_nvs
