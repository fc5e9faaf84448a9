// make_synthetic_scene: the package's built-in data. A seeded procedural street seen by a
// VoD-like camera, radar and LiDAR along a smooth drive, written in the View-of-Delft layout plus
// exact depth ground truth (depth_gt/NNNNN.npy).
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "common/cli.hpp"
#include "multimodal_nvs/core/synthetic/dataset.hpp"

namespace mm = multimodal_nvs;
namespace syn = multimodal_nvs::synthetic;

namespace {

void declareOptions(mm::cli::Args& args) {
  args.option("output", 1, "output directory (VoD layout root)");
  args.option("frames", 1, "number of frames", "16");
  args.option("first-frame", 1, "number of the first frame's files", "0");
  args.option("seed", 1, "random seed of the street and the sensor noise", "1");
  args.option("scale", 1, "image size relative to the VoD camera 1936x1216, e.g. 0.25", "1");
  args.option("supersample", 1, "colour rays per pixel per axis (0: 2 if scale <= 0.5, else 1)",
              "0");
  args.option("speed", 1, "driving speed in m/s (10 frames per second)", "4");
  args.option("camera-height", 1, "camera height above the road (m)", "1.3");
  args.option("camera-pitch", 1, "camera pitch above the horizon (deg, positive: looking up)", "0");
  args.option("vehicles", 1, "extra stopped cars, vans and trucks in the driving lanes", "0");
  args.option("pedestrians", 1, "pedestrians on the sidewalks and crossing ahead", "0");
  args.option("poles", 1, "extra posts at the curb", "0");
  args.option("radar-candidates", 1, "radar beam directions tried per scan (return density)",
              "1600");
  args.option("radar-range-sigma", 1, "radar range noise (m)", "0.1");
  args.option("radar-angle-sigma", 2, "radar azimuth and elevation noise (deg)", "0.25 0.5");
  args.option("radar-clutter", 1, "share of radar returns that are clutter", "0.05");
  args.option("lidar-beams", 1, "LiDAR beams: 16 (VLP-16), 32 (HDL-32E) or 64 (HDL-64E)", "64");
  args.option("lidar-range-sigma", 1, "LiDAR range noise (m)", "0.02");
  args.option("lidar-azimuth-step", 1, "LiDAR azimuth resolution (deg)", "0.2");
  args.option("jpeg-quality", 1, "JPEG quality of the camera images", "95");
  args.option("threads", 1, "worker threads (0: all cores)", "0");
  args.flag("quiet", "no progress bar");
}

std::uint64_t parseSeed(const std::string& text) {
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || text[0] == '-') {
    throw mm::cli::UsageError("--seed must be a non-negative integer, got '" + text + "'");
  }
  return v;
}

void progressBar(int done, int total) {
  const int width = 30, filled = done * width / total;
  std::cerr << "\rmake_synthetic_scene [" << std::string(filled, '#')
            << std::string(width - filled, '.') << "] " << done << "/" << total << " frames"
            << (done == total ? "\n" : "") << std::flush;
}

int run(int argc, char** argv) {
  mm::cli::Args args("make_synthetic_scene",
                     "Writes a deterministic synthetic street (camera, radar, LiDAR, poses, depth "
                     "ground truth) in the View-of-Delft layout.");
  declareOptions(args);
  if (!args.parse(argc, argv)) return 0;
  if (!args.has("output")) throw mm::cli::UsageError("--output DIR is required");

  syn::SyntheticDatasetParams p;
  p.frames = args.integer("frames", p.frames);
  p.first_frame = args.integer("first-frame", p.first_frame);
  p.seed = parseSeed(args.str("seed", "1"));
  p.scale = args.number("scale", p.scale);
  p.supersample = args.integer("supersample", p.supersample);
  p.path.speed = args.number("speed", p.path.speed);
  p.camera_height = args.number("camera-height", p.camera_height);
  p.camera_pitch_deg = args.number("camera-pitch", p.camera_pitch_deg);
  p.extra_vehicles = args.integer("vehicles", p.extra_vehicles);
  p.pedestrians = args.integer("pedestrians", p.pedestrians);
  p.extra_poles = args.integer("poles", p.extra_poles);
  p.radar.candidates = args.integer("radar-candidates", p.radar.candidates);
  const int beams = args.integer("lidar-beams", p.lidar.rings);
  if (beams != 16 && beams != 32 && beams != 64) {
    throw mm::cli::UsageError("--lidar-beams must be 16, 32 or 64, got " + std::to_string(beams));
  }
  p.lidar = syn::LidarParams::velodyne(beams);
  p.radar.range_sigma = args.number("radar-range-sigma", p.radar.range_sigma);
  if (args.has("radar-angle-sigma")) {
    const auto& a = args.list("radar-angle-sigma");
    p.radar.azimuth_sigma_deg = std::atof(a[0].c_str());
    p.radar.elevation_sigma_deg = std::atof(a[1].c_str());
  }
  p.radar.clutter_fraction = args.number("radar-clutter", p.radar.clutter_fraction);
  p.lidar.range_sigma = args.number("lidar-range-sigma", p.lidar.range_sigma);
  p.lidar.azimuth_step_deg = args.number("lidar-azimuth-step", p.lidar.azimuth_step_deg);
  p.jpeg_quality = args.integer("jpeg-quality", p.jpeg_quality);
  p.threads = args.integer("threads", 0);

  const auto start = std::chrono::steady_clock::now();
  const syn::SyntheticDataset dataset(p);
  const std::string root = args.str("output");
  const bool quiet = args.has("quiet");
  dataset.write(root, [quiet](int done, int total) {
    if (!quiet) progressBar(done, total);
  });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto& size = dataset.camera().size;
  std::ostringstream json;
  json << "{\"output\": \"" << mm::cli::jsonEscape(root) << "\", \"frames\": " << p.frames
       << ", \"first_frame\": " << p.first_frame << ", \"seed\": " << p.seed
       << ", \"width\": " << size.width << ", \"height\": " << size.height
       << ", \"seconds\": " << seconds << "}";
  std::cout << json.str() << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return mm::cli::runTool("make_synthetic_scene", run, argc, argv);
}
