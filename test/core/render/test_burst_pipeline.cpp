// The pipelined burst: every frame through the parallel stage once, the ordered stage in
// trajectory order, frames equal to the plain burst's whatever the thread counts and the bound on
// pending frames, and the first error of a stage stopping the burst.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/burst_pipeline.hpp"

namespace mm = multimodal_nvs;

namespace {

constexpr int kFrames = 9;
const mm::ImageSize kSize{24, 32};
const mm::PinholeIntrinsics kK{20.0, 20.0, 15.5, 11.5};

mm::ColoredCloud sceneCloud() {
  cv::Mat depth(kSize.height, kSize.width, CV_32FC1);
  for (int r = 0; r < kSize.height; ++r) {
    for (int c = 0; c < kSize.width; ++c)
      depth.at<float>(r, c) = 3.0f + 0.1f * c + 0.05f * r;
  }
  depth(cv::Rect(10, 8, 6, 5)).setTo(1.5f);
  cv::Mat image(kSize.height, kSize.width, CV_8UC3);
  cv::RNG(5).fill(image, cv::RNG::UNIFORM, 0, 256);
  return mm::backproject(depth, image, kK);
}

mm::Trajectory sceneTrajectory() {
  mm::Trajectory traj;
  traj.size = kSize;
  for (int i = 0; i < kFrames; ++i) {
    Eigen::Matrix4d w2c = Eigen::Matrix4d::Identity();
    w2c(0, 3) = 0.1 * i;
    w2c(2, 3) = -0.15 * i;
    traj.cameras.push_back({w2c, kK});
  }
  return traj;
}

bool sameMat(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  return a.size() == b.size() && a.type() == b.type() &&
         std::equal(a.data, a.data + a.total() * a.elemSize(), b.data);
}

}  // namespace

class BurstPipelineModes : public ::testing::TestWithParam<mm::SplatMode> {};

TEST_P(BurstPipelineModes, FramesMatchThePlainBurstInOrderForAnyThreadCount) {
  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  mm::SplatParams params;
  params.mode = GetParam();
  mm::PointSplatter single(1);
  const std::vector<mm::RenderedFrame> reference = single.render(cloud, traj, 0, kFrames, params);

  for (int threads : {1, 2, 3}) {
    for (int workers : {1, 2, 4}) {
      for (int pending : {0, 1, 3}) {
        const std::string at = "threads " + std::to_string(threads) + " workers " +
                               std::to_string(workers) + " pending " + std::to_string(pending);
        mm::PointSplatter splatter(threads);
        std::vector<int> parallel_seen(kFrames, 0), ordered;
        std::vector<mm::RenderedFrame> got(kFrames);
        std::mutex mutex;
        std::atomic<int> max_worker{0};
        mm::BurstFrameStages stages;
        stages.parallel = [&](int index, mm::RenderedFrame& frame, int worker) {
          std::lock_guard<std::mutex> lock(mutex);
          ++parallel_seen[static_cast<std::size_t>(index)];
          max_worker = std::max(max_worker.load(), worker);
          frame.depth.setTo(7.0f, frame.mask);  // the ordered stage sees what this stage did
        };
        stages.ordered = [&](int index, mm::RenderedFrame& frame) {
          ordered.push_back(index);  // one at a time: no lock needed
          got[static_cast<std::size_t>(index)] = frame;
        };
        mm::BurstPipelineOptions options;
        options.workers = workers;
        options.max_pending_frames = pending;
        const mm::BurstStats stats =
            mm::renderBurstPipelined(splatter, cloud, traj, params, stages, options);
        EXPECT_EQ(stats.frames, kFrames) << at;
        EXPECT_EQ(parallel_seen, std::vector<int>(kFrames, 1)) << at;
        EXPECT_EQ(ordered, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8})) << at;
        EXPECT_LT(max_worker.load(), workers) << at;
        for (int i = 0; i < kFrames; ++i) {
          const auto k = static_cast<std::size_t>(i);
          EXPECT_TRUE(sameMat(got[k].bgr, reference[k].bgr)) << at << " frame " << i;
          EXPECT_TRUE(sameMat(got[k].mask, reference[k].mask)) << at << " frame " << i;
          EXPECT_TRUE(sameMat(got[k].signed_bgr, reference[k].signed_bgr)) << at;
          cv::Mat depth = reference[k].depth.clone();
          depth.setTo(7.0f, reference[k].mask);
          EXPECT_TRUE(sameMat(got[k].depth, depth)) << at << " frame " << i;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(BurstPipeline, BurstPipelineModes,
                         ::testing::Values(mm::SplatMode::kGen3c, mm::SplatMode::kZbuffer));

TEST(BurstPipeline, ParallelStageErrorStopsTheBurstAndIsRethrown) {
  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  for (int workers : {1, 2}) {
    mm::PointSplatter splatter(2);
    std::vector<int> ordered;
    mm::BurstFrameStages stages;
    stages.parallel = [&](int index, mm::RenderedFrame&, int) {
      if (index == 3) throw std::runtime_error("cannot write PNG");
    };
    stages.ordered = [&](int index, mm::RenderedFrame&) { ordered.push_back(index); };
    mm::BurstPipelineOptions options;
    options.workers = workers;
    options.max_pending_frames = 2;
    EXPECT_THROW(mm::renderBurstPipelined(splatter, cloud, traj, {}, stages, options),
                 std::runtime_error);
    // Frames before the failed one may have passed the ordered stage, never frame 3 or later.
    for (std::size_t i = 0; i < ordered.size(); ++i)
      EXPECT_EQ(ordered[i], static_cast<int>(i));
    EXPECT_LE(ordered.size(), 3u);
  }
}

TEST(BurstPipeline, OrderedStageErrorStopsTheBurstAndIsRethrown) {
  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  mm::PointSplatter splatter(2);
  std::vector<int> ordered;
  mm::BurstFrameStages stages;
  stages.ordered = [&](int index, mm::RenderedFrame&) {
    if (index == 4) throw std::runtime_error("disk full");
    ordered.push_back(index);
  };
  mm::BurstPipelineOptions options;
  options.workers = 2;
  EXPECT_THROW(mm::renderBurstPipelined(splatter, cloud, traj, {}, stages, options),
               std::runtime_error);
  EXPECT_EQ(ordered, (std::vector<int>{0, 1, 2, 3}));
}

TEST(BurstPipeline, SplatterErrorIsRethrownAfterTheWorkersStop) {
  mm::PointSplatter splatter(2);
  mm::BurstFrameStages stages;
  stages.parallel = [](int, mm::RenderedFrame&, int) {};
  EXPECT_THROW(
      mm::renderBurstPipelined(splatter, mm::ColoredCloud{}, sceneTrajectory(), {}, stages),
      mm::InputError);
}
