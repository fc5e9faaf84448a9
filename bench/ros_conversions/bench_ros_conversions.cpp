// The depth nodelet's message conversions (Google Benchmark; no master): the coloured cloud of a
// VoD-sized frame (1936x1216, ~76 % of the pixels kept; config/lidar.yaml keeps 80 %) at a cloud
// stride of 1 and 2. At full resolution it is ~1.8 M points a frame: the node builds it on the
// callback's thread, so its time adds to the node's latency whenever depth/points has a subscriber.
// And the camera image in the depth models' BGR order: what an rgb8 camera costs every frame.
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <std_msgs/Header.h>
#include <opencv2/core.hpp>
#include <random>

#include "../benchmark_main.hpp"
#include "multimodal_nvs/core/depth/depth_completion.hpp"
#include "multimodal_nvs/ros/conversions.hpp"

namespace mm = multimodal_nvs;

namespace {

// A depth map on VoD's full-resolution grid with retention's kind of mask: the pixels with the
// largest variance dropped, here the top fifth of the rows (far and sky) and a few blocks.
mm::DepthMap vodSizedDepth() {
  mm::DepthMap map;
  map.grid = mm::StrideGrid{{1216, 1936}, 1};
  const std::size_t n = std::size_t(map.grid.size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> depth(2.0f, 100.0f), variance(0.01f, 25.0f);
  map.depth.resize(n);
  map.variance.resize(n);
  map.valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    map.depth[i] = depth(rng);
    map.variance[i] = variance(rng);
    const int r = static_cast<int>(i / 1936), c = static_cast<int>(i % 1936);
    map.valid[i] = r >= 1216 / 5 && !((r / 64 + c / 64) % 17 == 0);
  }
  return map;
}

void BM_ColoredCloud(benchmark::State& state) {
  static const mm::DepthMap map = vodSizedDepth();
  const mm::PinholeIntrinsics camera(1495.47, 1495.47, 961.27, 624.89);
  cv::Mat rgb(1216, 1936, CV_8UC3);
  cv::randu(rgb, cv::Scalar::all(0), cv::Scalar::all(255));
  std_msgs::Header header;
  header.frame_id = "camera";
  sensor_msgs::PointCloud2 cloud;
  // range(1): the pool's threads (the node passes the completer's pool; 1: the calling thread
  // only).
  mm::ThreadPool pool(static_cast<int>(state.range(1)));
  for (auto _ : state) {
    mm::ros_conversions::coloredCloud(map, camera, rgb, static_cast<int>(state.range(0)), header,
                                      cloud, &pool);
    benchmark::DoNotOptimize(cloud.data.data());
  }
  state.counters["points"] = static_cast<double>(cloud.width);
}
BENCHMARK(BM_ColoredCloud)
    ->Args({1, 1})
    ->Args({1, 2})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Unit(benchmark::kMillisecond);

/// A VoD-sized image message in the given encoding (range(0): 0 rgb8, 1 bgr8) to the BGR view the
/// depth models read: a channel swap for rgb8, a wrap without a copy for bgr8.
void BM_ImageToModelsBgr(benchmark::State& state) {
  sensor_msgs::Image image;
  image.encoding =
      state.range(0) == 0 ? sensor_msgs::image_encodings::RGB8 : sensor_msgs::image_encodings::BGR8;
  image.height = 1216;
  image.width = 1936;
  image.step = image.width * 3;
  image.data.resize(std::size_t(image.step) * image.height);
  cv::Mat pixels(int(image.height), int(image.width), CV_8UC3, image.data.data());
  cv::randu(pixels, cv::Scalar::all(0), cv::Scalar::all(255));
  cv::Mat bgr;
  for (auto _ : state) {
    if (!mm::ros_conversions::colourFromImage(image, mm::ros_conversions::ChannelOrder::kBgr, bgr)
             .ok()) {
      state.SkipWithError("conversion failed");
      break;
    }
    benchmark::DoNotOptimize(bgr.data);
  }
}
BENCHMARK(BM_ImageToModelsBgr)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  return mm::runBenchmarks(argc, argv);
}
