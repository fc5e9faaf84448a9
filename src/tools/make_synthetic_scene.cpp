// make_synthetic_scene: the package's built-in data. A seeded procedural street seen by a
// VoD-like camera, radar and LiDAR along a smooth drive, written in the View-of-Delft layout plus
// exact depth ground truth (depth_gt/NNNNN.npy).
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "common/cli.hpp"
#include "common/frame_options.hpp"
#include "common/progress.hpp"
#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/synthetic/dataset.hpp"

namespace mm = multimodal_nvs;
namespace syn = multimodal_nvs::synthetic;

namespace {

struct Options {
  syn::SyntheticDatasetParams p;
  std::string output, frames;
  std::vector<double> radar_angle_sigma;
  int lidar_beams = 64;
  bool radar_2d = false;
  bool quiet = false;
};

void declareOptions(CLI::App& app, Options& o) {
  syn::SyntheticDatasetParams& p = o.p;
  app.add_option("--output", o.output, "output directory (VoD layout root)")
      ->required()
      ->group(mm::cli::kRequired);
  const char* scene = "Scene";
  app.add_option("--num-frames", p.frames, "number of frames")
      ->check(mm::cli::atLeast(1))
      ->group(scene);
  app.add_option("--first-frame", p.first_frame, "number of the first frame's files")
      ->check(mm::cli::atLeast(0))
      ->group(scene);
  app.add_option("--frames", o.frames,
                 "the frames to write as one range A-B, as in the other tools (instead of "
                 "--first-frame and --num-frames)")
      ->group(scene);
  app.add_option("--seed", p.seed, "random seed of the street and the sensor noise")
      ->check(mm::cli::atLeast(0))
      ->group(scene);
  app.add_option("--scale", p.scale, "image size relative to the VoD camera 1936x1216, e.g. 0.25")
      ->check(mm::cli::positive())
      ->group(scene);
  app.add_option("--supersample", p.supersample,
                 "colour rays per pixel per axis (0: 2 if scale <= 0.5, else 1)")
      ->check(mm::cli::atLeast(0))
      ->group(scene);
  app.add_option("--speed", p.path.speed, "driving speed in m/s (10 frames per second)")
      ->check(mm::cli::finite())
      ->group(scene);
  app.add_option("--camera-height", p.camera_height, "camera height above the road (m)")
      ->check(mm::cli::positive())
      ->group(scene);
  app.add_option("--camera-pitch", p.camera_pitch_deg,
                 "camera pitch above the horizon (deg, positive: looking up)")
      ->check(mm::cli::finite())
      ->group(scene);
  app.add_option("--vehicles", p.extra_vehicles,
                 "extra stopped cars, vans and trucks in the driving lanes")
      ->group(scene);
  app.add_option("--pedestrians", p.pedestrians, "pedestrians on the sidewalks and crossing ahead")
      ->group(scene);
  app.add_option("--poles", p.extra_poles, "extra posts at the curb")->group(scene);
  const char* sensors = "Sensors";
  app.add_option("--radar-candidates", p.radar.candidates,
                 "radar beam directions tried per scan (return density)")
      ->check(mm::cli::atLeast(1))
      ->group(sensors);
  app.add_option("--lidar-beams", o.lidar_beams,
                 "LiDAR beams: 16 (VLP-16), 32 (HDL-32E) or 64 (HDL-64E)")
      ->check(CLI::IsMember({16, 32, 64}))
      ->group(sensors);
  app.add_option("--radar-range-sigma", p.radar.range_sigma, "radar range noise (m)")
      ->check(mm::cli::atLeast(0))
      ->group(sensors);
  app.add_option("--radar-angle-sigma", o.radar_angle_sigma,
                 "radar azimuth and elevation noise (deg)")
      ->expected(2)
      ->default_str(mm::json::number(p.radar.azimuth_sigma_deg).dump() + " " +
                    mm::json::number(p.radar.elevation_sigma_deg).dump())
      ->check(mm::cli::atLeast(0))
      ->group(sensors);
  app.add_option("--radar-clutter", p.radar.clutter_fraction,
                 "share of radar returns that are clutter")
      ->check(CLI::Range(0.0, 1.0))
      ->group(sensors);
  app.add_option("--radar-pass-through", p.radar.pass_through,
                 "share of radar detections from the surface behind the first one (under "
                 "vehicles, through foliage, multipath)")
      ->check(CLI::Range(0.0, 1.0))
      ->group(sensors);
  app.add_option("--radar-ghosts", p.radar.ghosts,
                 "share of radar detections that are multipath ghosts: along the beam, 1.1 to "
                 "--radar-ghost-max-factor times the surface's range, on no surface")
      ->check(CLI::Range(0.0, 1.0))
      ->group(sensors);
  app.add_option("--radar-ghost-max-factor", p.radar.ghost_range_factor_max,
                 "largest range factor of a ghost")
      ->check(CLI::Range(syn::kMinGhostRangeFactor, syn::kMaxGhostRangeFactor))
      ->group(sensors);
  app.add_flag("--radar-2d", o.radar_2d,
               "a 2D radar: range and azimuth measured, every detection reported at elevation 0 "
               "on the radar's own plane (as nuScenes' front radar)")
      ->group(sensors);
  app.add_option("--lidar-range-sigma", p.lidar.range_sigma, "LiDAR range noise (m)")
      ->check(mm::cli::atLeast(0))
      ->group(sensors);
  app.add_option("--lidar-azimuth-step", p.lidar.azimuth_step_deg, "LiDAR azimuth resolution (deg)")
      ->check(mm::cli::positive())
      ->group(sensors);
  app.add_option("--jpeg-quality", p.jpeg_quality, "JPEG quality of the camera images")
      ->check(CLI::Range(0, 100))
      ->group(sensors);
  app.add_option("--threads", p.threads, "worker threads (0: all cores)")
      ->check(mm::cli::atLeast(0))
      ->group(mm::cli::kOptions);
  app.add_flag("--quiet", o.quiet, "no progress or throughput on stderr")->group(mm::cli::kOptions);
}

/// --frames A-B: the shared frame-list syntax, restricted to one ascending range.
void applyFrameRange(const CLI::App& app, Options& o) {
  if (o.frames.empty()) return;
  if (mm::cli::given(app, "--num-frames") || mm::cli::given(app, "--first-frame")) {
    throw mm::cli::UsageError(
        "--frames replaces --first-frame and --num-frames; give one or the other");
  }
  const std::vector<int> frames = mm::cli::parseFrameList(o.frames);
  for (std::size_t i = 1; i < frames.size(); ++i) {
    if (frames[i] != frames[i - 1] + 1) {
      throw mm::cli::UsageError("--frames: the synthetic scene is one drive; give one range A-B");
    }
  }
  if (frames.size() == 1 && o.frames.find('-') == std::string::npos) {
    throw mm::cli::UsageError(
        "--frames " + o.frames + " would write the single frame " + o.frames +
        "; --frames is a frame list as in the other tools (for a count use --num-frames N)");
  }
  o.p.first_frame = frames.front();
  o.p.frames = static_cast<int>(frames.size());
}

int run(int argc, char** argv) {
  CLI::App app(
      "Writes a deterministic synthetic street (camera, radar, LiDAR, poses, depth ground "
      "truth) in the View-of-Delft layout.",
      "make_synthetic_scene");
  mm::cli::setUp(app, "make_synthetic_scene --output scene --num-frames 16 --scale 0.5 --seed 1");
  Options o;
  declareOptions(app, o);
  if (!mm::cli::parse(app, argc, argv)) return 0;
  applyFrameRange(app, o);
  syn::SyntheticDatasetParams& p = o.p;
  // The beam count picks a whole sensor model; the range noise and azimuth step given on the
  // command line apply on top of it.
  const double lidar_range_sigma = p.lidar.range_sigma,
               lidar_azimuth_step = p.lidar.azimuth_step_deg;
  p.lidar = syn::LidarParams::velodyne(o.lidar_beams);
  p.lidar.range_sigma = lidar_range_sigma;
  p.lidar.azimuth_step_deg = lidar_azimuth_step;
  p.radar.measures_elevation = !o.radar_2d;
  if (!o.radar_angle_sigma.empty()) {
    p.radar.azimuth_sigma_deg = o.radar_angle_sigma[0];
    p.radar.elevation_sigma_deg = o.radar_angle_sigma[1];
  }

  const auto start = std::chrono::steady_clock::now();
  const syn::SyntheticDataset dataset(p);
  const std::string& root = o.output;
  const bool quiet = o.quiet;
  mm::cli::Progress progress("make_synthetic_scene", p.frames, "frames", quiet);
  dataset.write(root, [&progress](int done, int) {
    while (progress.done() < done)
      progress.step();
  });
  progress.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto& size = dataset.camera().size;
  const mm::json::Json json = {{"output", root},
                               {"frames", p.frames},
                               {"first_frame", p.first_frame},
                               {"seed", p.seed},
                               {"width", size.width},
                               {"height", size.height},
                               {"seconds", mm::json::number(seconds, 6)}};
  std::cout << mm::json::oneLine(json) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("make_synthetic_scene", run, argc, argv);
}
