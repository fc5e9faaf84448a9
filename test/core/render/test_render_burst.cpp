// The burst entry point: frames independent of chunk size and thread count, handed over once each
// in order; the pipelined burst (parallel and ordered stages, errors); the depth resize rule; the
// GEN3C export of a burst (folder handling, size warning).
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <stdexcept>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/render/backprojection.hpp"
#include "multimodal_nvs/core/render/burst_pipeline.hpp"
#include "multimodal_nvs/core/render/render_burst.hpp"

namespace mm = multimodal_nvs;
namespace fs = std::filesystem;

namespace {

constexpr int kFrames = 7;
const mm::ImageSize kSize{24, 32};
const mm::PinholeIntrinsics kK{20.0, 20.0, 15.5, 11.5};

/// A slanted, textured surface seen from a camera moving sideways and forward: every frame
/// differs, and gen3c's per-batch depth normaliser differs between batches.
mm::ColoredCloud sceneCloud() {
  cv::Mat depth(kSize.height, kSize.width, CV_32FC1);
  for (int r = 0; r < kSize.height; ++r) {
    for (int c = 0; c < kSize.width; ++c)
      depth.at<float>(r, c) = 3.0f + 0.1f * c + 0.05f * r;
  }
  depth(cv::Rect(10, 8, 6, 5)).setTo(1.5f);  // a box in front: occlusion and holes
  cv::Mat image(kSize.height, kSize.width, CV_8UC3);
  cv::RNG(11).fill(image, cv::RNG::UNIFORM, 0, 256);
  return mm::backproject(depth, image, kK);
}

mm::Trajectory sceneTrajectory() {
  mm::Trajectory traj;
  traj.size = kSize;
  for (int i = 0; i < kFrames; ++i) {
    Eigen::Matrix4d w2c = Eigen::Matrix4d::Identity();
    w2c(0, 3) = 0.15 * i;
    w2c(2, 3) = -0.2 * i;
    traj.cameras.push_back({w2c, kK});
  }
  return traj;
}

bool sameMat(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  if (a.size() != b.size() || a.type() != b.type()) return false;
  const std::size_t bytes = a.total() * a.elemSize();
  return std::equal(a.data, a.data + bytes, b.data);
}

void expectSameFrame(const mm::RenderedFrame& a, const mm::RenderedFrame& b,
                     const std::string& at) {
  EXPECT_TRUE(sameMat(a.bgr, b.bgr)) << at;
  EXPECT_TRUE(sameMat(a.mask, b.mask)) << at;
  EXPECT_TRUE(sameMat(a.depth, b.depth)) << at;
  EXPECT_TRUE(sameMat(a.signed_bgr, b.signed_bgr)) << at;
}

mm::RenderedFrame deepCopy(const mm::RenderedFrame& f) {
  return {f.bgr.clone(), f.mask.clone(), f.depth.clone(), f.signed_bgr.clone()};
}

std::string tempDir(const std::string& name) {
  return "/tmp/mmnvs_test_burst_" + name + "_" + std::to_string(::getpid());
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

/// The scene in one splat mode, with the reference: every frame in one render call on one thread.
class BurstModes : public ::testing::TestWithParam<mm::SplatMode> {
 protected:
  void SetUp() override {
    params.mode = GetParam();
    mm::PointSplatter single(1);
    reference = single.render(cloud, traj, 0, kFrames, params);
  }

  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  mm::SplatParams params;
  std::vector<mm::RenderedFrame> reference;
};

TEST_P(BurstModes, FramesDoNotDependOnChunkSizeOrThreads) {
  ASSERT_EQ(reference.size(), std::size_t(kFrames));
  EXPECT_GT(cv::countNonZero(reference[0].mask), 0);
  EXPECT_FALSE(sameMat(reference[0].bgr, reference[kFrames - 1].bgr));  // the views differ

  for (int threads : {1, 2, 3}) {
    mm::PointSplatter splatter(threads);
    for (int chunk : {0, 1, 2, 3, 5, kFrames, 100}) {
      std::vector<mm::RenderedFrame> got;
      mm::renderBurst(
          splatter, cloud, traj, params,
          [&](int, const mm::RenderedFrame& frame) { got.push_back(deepCopy(frame)); },
          mm::BurstOptions{chunk});
      ASSERT_EQ(got.size(), reference.size());
      for (int i = 0; i < kFrames; ++i) {
        expectSameFrame(got[std::size_t(i)], reference[std::size_t(i)],
                        "threads " + std::to_string(threads) + " chunk " + std::to_string(chunk) +
                            " frame " + std::to_string(i));
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RenderBurst, BurstModes,
                         ::testing::Values(mm::SplatMode::kGen3c, mm::SplatMode::kZbuffer));

TEST(RenderBurst, SinkSeesEveryIndexOnceInOrder) {
  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  mm::PointSplatter splatter(2);
  for (int chunk : {1, 3, 4, kFrames}) {
    std::vector<int> indices;
    const mm::BurstStats stats = mm::renderBurst(
        splatter, cloud, traj, {},
        [&](int index, const mm::RenderedFrame&) { indices.push_back(index); },
        mm::BurstOptions{chunk});
    EXPECT_EQ(indices, (std::vector<int>{0, 1, 2, 3, 4, 5, 6})) << "chunk " << chunk;
    EXPECT_EQ(stats.frames, kFrames);
    EXPECT_EQ(stats.chunks, (kFrames + chunk - 1) / chunk);
    EXPECT_GE(stats.render_ms, 0.0);
  }
}

TEST(RenderBurst, ChunkSinkGetsConsecutiveChunksOfTheChosenSize) {
  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  mm::PointSplatter splatter(2);
  std::vector<std::pair<int, std::size_t>> chunks;
  mm::renderBurstChunks(splatter, cloud, traj, {},
                        [&](int first, const std::vector<mm::RenderedFrame>& frames) {
                          chunks.emplace_back(first, frames.size());
                        });
  // Default: two frames per worker thread.
  EXPECT_EQ(chunks, (std::vector<std::pair<int, std::size_t>>{{0, 4}, {4, 3}}));
}

TEST(RenderBurst, ChunkPolicy) {
  EXPECT_EQ(mm::BurstOptions{}.chunkFramesFor(1), 2);
  EXPECT_EQ(mm::BurstOptions{}.chunkFramesFor(2), 4);
  EXPECT_EQ(mm::BurstOptions{}.chunkFramesFor(8), 16);
  EXPECT_EQ(mm::BurstOptions{3}.chunkFramesFor(8), 3);
}

TEST(RenderBurst, SinkErrorStopsTheBurst) {
  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  mm::PointSplatter splatter(1);
  int seen = 0;
  EXPECT_THROW(mm::renderBurst(
                   splatter, cloud, traj, {},
                   [&](int index, const mm::RenderedFrame&) {
                     ++seen;
                     if (index == 2) throw std::runtime_error("disk full");
                   },
                   mm::BurstOptions{2}),
               std::runtime_error);
  EXPECT_EQ(seen, 3);
}

TEST(RenderBurst, EmptyCloudThrowsInputError) {
  mm::PointSplatter splatter(1);
  EXPECT_THROW(mm::renderBurst(splatter, mm::ColoredCloud{}, sceneTrajectory(), {},
                               [](int, const mm::RenderedFrame&) {}),
               mm::InputError);
}

TEST_P(BurstModes, PipelinedFramesMatchThePlainBurstInOrderForAnyThreadCount) {
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
        EXPECT_EQ(ordered, (std::vector<int>{0, 1, 2, 3, 4, 5, 6})) << at;
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

TEST(DepthResize, ParseAndName) {
  for (mm::DepthResize d : {mm::DepthResize::kAuto, mm::DepthResize::kYes, mm::DepthResize::kNo}) {
    EXPECT_EQ(mm::parseDepthResize(mm::toString(d)), d);
  }
  EXPECT_EQ(mm::parseDepthResize("maybe"), std::nullopt);
  EXPECT_EQ(mm::parseDepthResize("Auto"), std::nullopt);
}

TEST(DepthResize, TruthTableForAnyGrid) {
  using D = mm::DepthResize;
  using M = mm::SplatMode;
  EXPECT_TRUE(mm::resizesDepthToRender(D::kAuto, M::kGen3c));
  EXPECT_FALSE(mm::resizesDepthToRender(D::kAuto, M::kZbuffer));
  EXPECT_TRUE(mm::resizesDepthToRender(D::kYes, M::kGen3c));
  EXPECT_TRUE(mm::resizesDepthToRender(D::kYes, M::kZbuffer));
  EXPECT_FALSE(mm::resizesDepthToRender(D::kNo, M::kGen3c));
  EXPECT_FALSE(mm::resizesDepthToRender(D::kNo, M::kZbuffer));
}

TEST(DepthResize, TruthTableForAKnownGrid) {
  using D = mm::DepthResize;
  using M = mm::SplatMode;
  const mm::ImageSize render{704, 1280};
  const mm::ImageSize full{1216, 1936}, same{704, 1280}, stride2{608, 968}, narrow{800, 1000};
  EXPECT_TRUE(mm::resizesDepthToRender(D::kAuto, M::kGen3c, full, render));
  EXPECT_TRUE(mm::resizesDepthToRender(D::kAuto, M::kGen3c, same, render));
  EXPECT_FALSE(mm::resizesDepthToRender(D::kAuto, M::kGen3c, stride2, render));
  EXPECT_FALSE(mm::resizesDepthToRender(D::kAuto, M::kGen3c, narrow, render));  // one axis short
  EXPECT_FALSE(mm::resizesDepthToRender(D::kAuto, M::kZbuffer, full, render));
  EXPECT_TRUE(mm::resizesDepthToRender(D::kYes, M::kZbuffer, stride2, render));
  EXPECT_TRUE(mm::resizesDepthToRender(D::kYes, M::kGen3c, stride2, render));
  EXPECT_FALSE(mm::resizesDepthToRender(D::kNo, M::kGen3c, full, render));
}

TEST(Gen3cBurstExport, SizeWarningOnlyOffGen3cSize) {
  EXPECT_EQ(mm::gen3cSizeWarning(121, {704, 1280}), std::nullopt);
  EXPECT_EQ(mm::gen3cSizeWarning(16, {352, 640}).value_or(""),
            "GEN3C expects 121 frames at 704x1280; the export uses the requested 16 frames at "
            "352x640");
  EXPECT_TRUE(mm::gen3cSizeWarning(121, {704, 640}).has_value());
  EXPECT_TRUE(mm::gen3cSizeWarning(120, {704, 1280}).has_value());
}

TEST(Gen3cBurstExport, RenameWhenCompleteReplacesTheFolderAtFinishOnly) {
  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  mm::PointSplatter splatter(1);
  const std::vector<mm::RenderedFrame> frames = splatter.render(cloud, traj, 0, kFrames, {});
  cv::Mat image(kSize.height, kSize.width, CV_8UC3, cv::Scalar(10, 20, 30));
  const std::string root = tempDir("rename");
  fs::remove_all(root);
  // Reference: the writer and companions straight into a folder, as the tool writes them.
  {
    mm::Gen3cBurstExport direct(root + "/direct", image, kFrames, kSize,
                                mm::Gen3cFolderWrite::kInPlace);
    for (const auto& f : frames)
      direct.append(f);
    EXPECT_TRUE(fs::exists(root + "/direct/rendered_warp_images.npy"));
    direct.finish();
    EXPECT_EQ(direct.folder(), root + "/direct");
  }
  const std::string folder = root + "/0000000001_000000002";
  fs::create_directories(folder);
  std::ofstream(folder + "/stale.txt") << "previous export";
  {
    mm::Gen3cBurstExport exporter(folder, image, kFrames, kSize,
                                  mm::Gen3cFolderWrite::kRenameWhenComplete);
    for (const auto& f : frames)
      exporter.append(f);
    EXPECT_TRUE(fs::exists(folder + ".partial/rendered_warp_images.npy"));
    EXPECT_TRUE(fs::exists(folder + "/stale.txt"));  // the old folder stays until complete
    exporter.finish();
  }
  EXPECT_FALSE(fs::exists(folder + ".partial"));
  EXPECT_FALSE(fs::exists(folder + "/stale.txt"));
  for (const char* name :
       {"rendered_warp_images.npy", "rendered_warp_masks.npy", "input_image.png", "README.md"}) {
    const std::string got = fileBytes(folder + "/" + name);
    EXPECT_FALSE(got.empty()) << name;
    EXPECT_EQ(got, fileBytes(root + "/direct/" + name)) << name;
  }
  fs::remove_all(root);
}

TEST(Gen3cBurstExport, IncompleteBurstIsNotRenamed) {
  const mm::ColoredCloud cloud = sceneCloud();
  const mm::Trajectory traj = sceneTrajectory();
  mm::PointSplatter splatter(1);
  const std::vector<mm::RenderedFrame> frames = splatter.render(cloud, traj, 0, 2, {});
  const std::string root = tempDir("incomplete");
  fs::remove_all(root);
  const std::string folder = root + "/export";
  {
    mm::Gen3cBurstExport exporter(folder, cv::Mat(kSize.height, kSize.width, CV_8UC3), kFrames,
                                  kSize, mm::Gen3cFolderWrite::kRenameWhenComplete);
    for (const auto& f : frames)
      exporter.append(f);
    EXPECT_THROW(exporter.finish(), mm::InputError);  // 2 of 7 frames
  }
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_TRUE(fs::exists(folder + ".partial"));
  fs::remove_all(root);
}
