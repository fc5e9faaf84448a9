// bench/compare_builds.py end to end: a snapshot of this build compares equal to it, a build whose
// tool computes something else is caught file by file, timing rounds alternate and summarise, and
// a missing tool or a tool that fails is an error that names it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "tool_runner.hpp"

namespace fs = std::filesystem;
using multimodal_nvs::test::runCommand;
using multimodal_nvs::test::runTool;

namespace {

// The devel space the tools under test come from (MMNVS_TOOL_DIR is its lib/multimodal_nvs).
std::string develSpace() {
  return fs::path(MMNVS_TOOL_DIR).parent_path().parent_path().string();
}

std::string freshDir(const std::string& name) {
  const fs::path path = fs::path(::testing::TempDir()) / name;
  fs::remove_all(path);
  return path.string();
}

// A tiny synthetic scene in VoD's layout, made once for the whole file.
const std::string& scene() {
  static const std::string path = [] {
    const std::string scene = freshDir("compare_builds_scene");
    const auto made = runTool("make_synthetic_scene",
                              "--output " + scene + " --scale 0.2 --num-frames 1 --quiet");
    EXPECT_EQ(made.exit_code, 0) << made.output;
    return scene;
  }();
  return path;
}

std::string compareBuilds(const std::string& args) {
  return "bench/compare_builds.py " + args;
}

}  // namespace

TEST(CompareBuilds, ASnapshotOfThisBuildGivesIdenticalOutputs) {
  const std::string snapshot = freshDir("compare_builds_snapshot");
  const auto snap = runCommand(compareBuilds("snapshot " + develSpace() + " " + snapshot));
  ASSERT_EQ(snap.exit_code, 0) << snap.output;
  ASSERT_TRUE(fs::exists(snapshot + "/lib/multimodal_nvs/complete_depth"));
  const auto same = runCommand(compareBuilds("same " + snapshot + " " + develSpace() +
                                             " -- complete_depth --vod-root " + scene() +
                                             " --frame 0 --model image_guided"));
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("identical: 3 files (out_depth.npy, out_valid.npy, out_variance.npy)"),
            std::string::npos)
      << same.output;
  // A snapshot is never written over.
  const auto again = runCommand(compareBuilds("snapshot " + develSpace() + " " + snapshot));
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("exists"), std::string::npos) << again.output;
}

TEST(CompareBuilds, ABuildThatComputesSomethingElseIsCaughtFileByFile) {
  // The "after" build: its complete_depth is the real one with another length scale.
  const std::string other = freshDir("compare_builds_other");
  fs::create_directories(other + "/lib/multimodal_nvs");
  const std::string wrapper = other + "/lib/multimodal_nvs/complete_depth";
  {
    std::ofstream script(wrapper);
    script << "#!/bin/sh\nexec " << MMNVS_TOOL_DIR
           << "/complete_depth \"$@\" --kernel-length-scale-deg 0.3\n";
  }
  fs::permissions(wrapper, fs::perms::owner_all, fs::perm_options::add);
  const auto same = runCommand(compareBuilds("same " + develSpace() + " " + other +
                                             " -- complete_depth --vod-root " + scene() +
                                             " --frame 0 --model kernel"));
  EXPECT_EQ(same.exit_code, 1) << same.output;
  EXPECT_NE(same.output.find("out_depth.npy: differs"), std::string::npos) << same.output;
  EXPECT_NE(same.output.find("files differ"), std::string::npos) << same.output;
}

TEST(CompareBuilds, TimingRoundsAlternateAndAreSummarised) {
  const auto timed = runCommand(compareBuilds("time " + develSpace() + " " + develSpace() +
                                              " --rounds 3 -- complete_depth --vod-root " +
                                              scene() + " --frame 0 --model nearest --repeat 2"));
  ASSERT_EQ(timed.exit_code, 0) << timed.output;
  // Round 1 runs before then after, round 2 after then before, round 3 before then after.
  EXPECT_TRUE(std::regex_search(timed.output, std::regex("round 1: before [0-9.]+, after [0-9.]+")))
      << timed.output;
  EXPECT_TRUE(std::regex_search(timed.output, std::regex("round 2: after [0-9.]+, before [0-9.]+")))
      << timed.output;
  EXPECT_TRUE(std::regex_search(timed.output, std::regex("round 3: before [0-9.]+, after [0-9.]+")))
      << timed.output;
  std::smatch row;
  ASSERT_TRUE(std::regex_search(
      timed.output, row, std::regex("median_ms +([0-9.]+) +([0-9.]+) +([0-9.]+) +([0-3]) of 3")))
      << timed.output;
  const double before = std::stod(row[1]), after = std::stod(row[2]), ratio = std::stod(row[3]);
  EXPECT_GT(before, 0.0);
  EXPECT_GT(after, 0.0);
  EXPECT_NEAR(ratio, after / before, 1e-3 + 1e-3 * ratio);
}

TEST(CompareBuilds, AMissingToolOrAFailingRunIsAnErrorThatNamesIt) {
  const std::string empty = freshDir("compare_builds_empty");
  const auto missing = runCommand(
      compareBuilds("time " + empty + " " + develSpace() + " -- complete_depth --repeat 2"));
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find(empty + "/lib/multimodal_nvs/complete_depth"), std::string::npos)
      << missing.output;
  const auto failing =
      runCommand(compareBuilds("same " + develSpace() + " " + develSpace() +
                               " -- complete_depth --vod-root " + empty + " --frame 0"));
  EXPECT_EQ(failing.exit_code, 3) << failing.output;
  EXPECT_NE(failing.output.find("complete_depth"), std::string::npos) << failing.output;
  EXPECT_NE(failing.output.find("exited with"), std::string::npos) << failing.output;
  const auto no_time = runCommand(compareBuilds("time " + develSpace() + " " + develSpace() +
                                                " --rounds 1 -- complete_depth --vod-root " +
                                                scene() + " --frame 0 --model nearest"));
  EXPECT_EQ(no_time.exit_code, 3) << no_time.output;
  EXPECT_NE(no_time.output.find("median_ms"), std::string::npos) << no_time.output;
  const auto no_tool = runCommand(compareBuilds("time " + develSpace() + " " + develSpace()));
  EXPECT_EQ(no_tool.exit_code, 2) << no_tool.output;
}
