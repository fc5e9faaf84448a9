// Rendering speed of the conditioning splatter: 121 frames at 704x1280 from a synthetic
// full-resolution (1216x1936, 2.35 M points) depth map, in both splat modes.
// Run: devel/lib/multimodal_nvs/bench_render (after make build; scripts/devel_dir.sh)
//      --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/core.hpp>

#include "benchmark_main.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/render_burst.hpp"
#include "multimodal_nvs/core/render/splatting.hpp"
#include "multimodal_nvs/core/render/trajectory.hpp"

namespace mm = multimodal_nvs;

namespace {

constexpr int kSourceHeight = 1216, kSourceWidth = 1936;

/// VoD-like camera (P2 of the shared calibration, rounded).
mm::PinholeIntrinsics sourceIntrinsics() {
  return {1495.5, 1495.5, 961.3, 624.9};
}

/// A street-like depth map: ground plane below the horizon, a far wall above, and boxes in front,
/// every pixel kept, so the cloud has the full 2.35 M points.
const mm::ColoredCloud& syntheticCloud() {
  static const mm::ColoredCloud cloud = [] {
    const mm::PinholeIntrinsics k = sourceIntrinsics();
    cv::Mat depth(kSourceHeight, kSourceWidth, CV_32FC1);
    cv::Mat image(kSourceHeight, kSourceWidth, CV_8UC3);
    cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(256));
    for (int v = 0; v < kSourceHeight; ++v) {
      for (int u = 0; u < kSourceWidth; ++u) {
        const double ray_y = (v - k.cy) / k.fy;
        double z = 60.0;                                    // far wall
        if (ray_y > 1e-3) z = std::min(60.0, 1.5 / ray_y);  // ground 1.5 m below the camera
        if ((u / 200) % 3 == 1 && v > 400 && v < 900) z = std::min(z, 8.0 + (u / 200) * 2.0);
        depth.at<float>(v, u) = static_cast<float>(z);
      }
    }
    return mm::backproject(depth, image, k);
  }();
  return cloud;
}

/// 16 recorded-like poses: 0.6 m forward and 2 deg yaw per step, resampled to 121 frames.
mm::Trajectory drivingTrajectory() {
  std::vector<Eigen::Matrix4d> poses;
  for (int i = 0; i < 16; ++i) {
    Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
    c2w.topLeftCorner<3, 3>() =
        Eigen::AngleAxisd(i * 2.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    c2w(2, 3) = 0.6 * i;
    poses.push_back(c2w);
  }
  const mm::PinholeIntrinsics target =
      sourceIntrinsics().scaledTo(kSourceHeight, kSourceWidth, 704, 1280);
  return mm::recordedTrajectory(poses, 121, target, {704, 1280});
}

void renderAll(benchmark::State& state, mm::SplatMode mode) {
  const mm::ColoredCloud& cloud = syntheticCloud();
  const mm::Trajectory traj = drivingTrajectory();
  mm::PointSplatter splatter(static_cast<int>(state.range(0)));
  mm::SplatParams params;
  params.mode = mode;
  for (auto _ : state) {
    mm::renderBurstChunks(splatter, cloud, traj, params,
                          [](int, const std::vector<mm::RenderedFrame>& frames) {
                            benchmark::DoNotOptimize(frames.front().bgr.data);
                          });
  }
  state.counters["points"] = static_cast<double>(cloud.size());
  state.counters["threads"] = splatter.threads();
}

void BM_Render121Zbuffer(benchmark::State& state) {
  renderAll(state, mm::SplatMode::kZbuffer);
}
void BM_Render121Gen3c(benchmark::State& state) {
  renderAll(state, mm::SplatMode::kGen3c);
}

}  // namespace

// One run per thread count (2, then 1): a full 121-frame trajectory per iteration.
static void renderCases(benchmark::internal::Benchmark* b) {
  b->Arg(2)
      ->Arg(1)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(1)
      ->MeasureProcessCPUTime()
      ->UseRealTime();
}

BENCHMARK(BM_Render121Zbuffer)->Apply(renderCases);
BENCHMARK(BM_Render121Gen3c)->Apply(renderCases);

int main(int argc, char** argv) {
  return multimodal_nvs::runBenchmarks(argc, argv);
}
