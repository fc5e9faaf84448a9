// The analysis scripts (scripts/*.py) end to end on small synthetic scenes: they read what the
// tools write, their numbers mean what their help says, and bad input names the file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "multimodal_nvs/core/common/json_output.hpp"
#include "multimodal_nvs/core/io/npy.hpp"
#include "tool_runner.hpp"

namespace io = multimodal_nvs::io;
using multimodal_nvs::test::runCommand;
using multimodal_nvs::test::runTool;

namespace {

std::string dir() {
  return ::testing::TempDir();
}

std::string makeScene(const std::string& name, const std::string& args = "") {
  const std::string scene = dir() + name;
  const auto made = runTool("make_synthetic_scene",
                            "--output " + scene + " --scale 0.2 --num-frames 3 --quiet " + args);
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return scene;
}

struct GapRow {
  std::string label;
  double share = NAN;  // the region's share of the image (region rows only)
  double covered_psnr = NAN, coverage = NAN, preview_psnr = NAN;
};

/// The rows of novel_view_gap_by_region.py's table, in order.
std::vector<GapRow> gapRows(const std::string& output) {
  std::vector<GapRow> rows;
  const std::regex row(R"(^(model|oracle|model, oracle (.*) \(([0-9.]+)\))\s+([-0-9.]+)\s+)"
                       R"(([0-9.]+)\s+([-0-9.]+)(\s+[-0-9]+%)?\s*$)");
  std::size_t start = 0;
  while (start < output.size()) {
    std::size_t end = output.find('\n', start);
    if (end == std::string::npos) end = output.size();
    const std::string line = output.substr(start, end - start);
    std::smatch m;
    if (std::regex_match(line, m, row)) {
      GapRow r;
      r.label = m[2].matched ? m[2].str() : m[1].str();
      if (m[3].matched) r.share = std::stod(m[3]);
      r.covered_psnr = std::stod(m[4]);
      r.coverage = std::stod(m[5]);
      r.preview_psnr = std::stod(m[6]);
      rows.push_back(r);
    }
    start = end + 1;
  }
  return rows;
}

multimodal_nvs::test::ToolResult gapByRegion(const std::string& scene, const std::string& prefix,
                                             const std::string& extra = "") {
  return runCommand("scripts/novel_view_gap_by_region.py " + scene + " " + prefix + " --tools " +
                    std::string(MMNVS_TOOL_DIR) + " --size 88 160" + extra);
}

/// "behind X" of radar_surface_offsets.py: the share of returns 20 % or more behind the surface.
double shareBehind(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex(R"(\(behind ([0-9.]+),)"))) return NAN;
  return std::stod(m[1]);
}

}  // namespace

// The exact depth itself: every pasted region leaves it unchanged, so every row equals the oracle;
// a model's depth: the three regions tile the image and the too-near / too-far parts lie inside
// the region above the highest return.
TEST(NovelViewGapByRegion, TheExactDepthLosesNothingAndTheRegionsTileTheImage) {
  const std::string scene = makeScene("gap_scene");
  const io::NpyArray exact = io::readNpy(scene + "/depth_gt/00000.npy");
  std::vector<float> oracle = exact.asFloat();
  for (float& d : oracle)
    d = d > 0.0f ? d : 100.0f;
  io::writeNpy(dir() + "gap_exact_depth.npy", oracle.data(), exact.shape);
  const auto same = gapByRegion(scene, dir() + "gap_exact");
  ASSERT_EQ(same.exit_code, 0) << same.output;
  const std::vector<GapRow> exact_rows = gapRows(same.output);
  ASSERT_EQ(exact_rows.size(), 7u) << same.output;
  for (const GapRow& r : exact_rows) {
    EXPECT_EQ(r.covered_psnr, exact_rows.back().covered_psnr) << r.label;
    EXPECT_EQ(r.coverage, exact_rows.back().coverage) << r.label;
  }

  const auto model =
      runTool("complete_depth", "--vod-root " + scene + " --frame 0 --sensor lidar " +
                                    "--model nearest --output " + dir() + "gap_model");
  ASSERT_EQ(model.exit_code, 0) << model.output;
  const auto gap = gapByRegion(scene, dir() + "gap_model");
  ASSERT_EQ(gap.exit_code, 0) << gap.output;
  const std::vector<GapRow> rows = gapRows(gap.output);
  ASSERT_EQ(rows.size(), 7u) << gap.output;
  EXPECT_EQ(rows.front().label, "model");
  EXPECT_EQ(rows.back().label, "oracle");
  const double above = rows[1].share, too_near = rows[2].share, too_far = rows[3].share;
  const double below = rows[4].share, sky = rows[5].share;
  EXPECT_GT(above, 0.0) << "a LiDAR's highest ring leaves part of the image above it";
  EXPECT_GT(sky, 0.0);
  EXPECT_NEAR(above + below + sky, 1.0, 0.002) << gap.output;
  EXPECT_LE(too_near + too_far, above + 0.001) << gap.output;
  EXPECT_EQ(rows.back().covered_psnr, exact_rows.back().covered_psnr)
      << "the oracle row renders the exact depth whatever the model";
}

// By the model's errors (radar input): too near, too far, within 10 % and the sky tile the image,
// and pasting the exact depth where a model is too near moves its frames towards the oracle's.
TEST(NovelViewGapByRegion, ByErrorTheRegionsTileTheImage) {
  const std::string scene = makeScene("gap_error_scene");
  const auto model =
      runTool("complete_depth", "--vod-root " + scene + " --frame 0 --sensor radar " +
                                    "--model constant --output " + dir() + "gap_error_model");
  ASSERT_EQ(model.exit_code, 0) << model.output;
  const auto gap = gapByRegion(scene, dir() + "gap_error_model", " --by-error");
  ASSERT_EQ(gap.exit_code, 0) << gap.output;
  const std::vector<GapRow> rows = gapRows(gap.output);
  ASSERT_EQ(rows.size(), 6u) << gap.output;
  EXPECT_EQ(rows[1].label, "> 10 % too near");
  EXPECT_EQ(rows[2].label, "> 10 % too far");
  EXPECT_EQ(rows[3].label, "within 10 %");
  EXPECT_EQ(rows[4].label, "sky");
  const double near = rows[1].share, far = rows[2].share, within = rows[3].share;
  EXPECT_NEAR(near + far + within + rows[4].share, 1.0, 0.002) << gap.output;
  // One depth for the whole image (the median return's) is too near for the far part of the street
  // and too far for the near part.
  EXPECT_GT(near, 0.05) << gap.output;
  EXPECT_GT(far, 0.05) << gap.output;
  const double model_psnr = rows.front().covered_psnr, oracle_psnr = rows.back().covered_psnr;
  ASSERT_GT(oracle_psnr, model_psnr) << gap.output;
  EXPECT_GT(rows[1].covered_psnr, model_psnr + 1.0) << gap.output;
}

TEST(NovelViewGapByRegion, AMissingOrMisSizedDepthFailsNamingTheFile) {
  const std::string scene = makeScene("gap_bad_scene");
  const auto missing = gapByRegion(scene, dir() + "gap_nothing_here");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("gap_nothing_here_depth.npy"), std::string::npos) << missing.output;
  const float small[4] = {1, 2, 3, 4};
  io::writeNpy(dir() + "gap_small_depth.npy", small, {2, 2});
  const auto wrong = gapByRegion(scene, dir() + "gap_small");
  EXPECT_NE(wrong.exit_code, 0);
  EXPECT_NE(wrong.output.find("shape (2, 2)"), std::string::npos) << wrong.output;
}

// The synthetic radar's pass-through (returns from behind the first surface) is what the script
// was written to see: with it, more returns lie 20 % or more behind the LiDAR's surface.
TEST(RadarSurfaceOffsets, PassThroughPutsMoreReturnsBehindTheSurface) {
  const std::string plain = makeScene("offsets_plain", "--seed 3");
  const std::string through = makeScene("offsets_through", "--seed 3 --radar-pass-through 0.9");
  const auto a = runCommand("scripts/radar_surface_offsets.py " + plain + " 00000");
  const auto b = runCommand("scripts/radar_surface_offsets.py " + through + " 00000");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_GT(shareBehind(b.output), shareBehind(a.output) + 0.1) << a.output << b.output;
  const auto bad = runCommand("scripts/radar_surface_offsets.py " + dir() + "no_such_scene 00000");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("no_such_scene"), std::string::npos) << bad.output;
}

// eval_tables.py common: the MAE of each model over the pixels every model predicts equals what the
// saved errors give, their share is below 1 when one model (linear, inside the returns' hull) does
// not predict everywhere, the per-pixel files go afterwards, and errors of different truths fail.
TEST(EvalTablesCommon, EachModelIsScoredOnThePixelsAllOfThemPredict) {
  const std::string scene = makeScene("common_scene", "--seed 5");
  const std::string out = dir() + "common_out";
  std::filesystem::remove_all(out);
  for (const std::string model : {"nearest", "linear"}) {
    const auto r =
        runTool("evaluate_depth", "--vod-root " + scene + " --frames 0 --quiet " + "--model " +
                                      model + " --save-errors " + out + "/errors/radar_" + model);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const auto reduced = runCommand("scripts/eval_tables.py common " + out + " --keep");
  ASSERT_EQ(reduced.exit_code, 0) << reduced.output;
  std::ifstream in(out + "/radar_common.json");
  ASSERT_TRUE(in.good());
  const auto doc = nlohmann::json::parse(in);
  const std::vector<float> nearest =
      io::readNpy(out + "/errors/radar_nearest/00000_errors.npy").asFloat();
  const std::vector<float> linear =
      io::readNpy(out + "/errors/radar_linear/00000_errors.npy").asFloat();
  ASSERT_EQ(nearest.size(), linear.size());
  double sum_nearest = 0.0, sum_linear = 0.0;
  std::size_t common = 0, nearest_predicted = 0;
  for (std::size_t i = 0; i < nearest.size(); ++i) {
    nearest_predicted += std::isfinite(nearest[i]);
    if (!std::isfinite(nearest[i]) || !std::isfinite(linear[i])) continue;
    ++common;
    sum_nearest += std::abs(nearest[i]);
    sum_linear += std::abs(linear[i]);
  }
  ASSERT_GT(common, 0u);
  EXPECT_EQ(nearest_predicted, nearest.size());  // nearest predicts every pixel
  EXPECT_LT(common, nearest.size());             // linear does not
  const auto& mean = doc["mean_over_frames"];
  EXPECT_NEAR(mean["share"].get<double>(), double(common) / nearest.size(), 1e-9);
  EXPECT_NEAR(mean["mae"]["nearest"].get<double>(), sum_nearest / common, 1e-4);
  EXPECT_NEAR(mean["mae"]["linear"].get<double>(), sum_linear / common, 1e-4);
  EXPECT_EQ(doc["frames"][0]["truth_pixels"].get<std::size_t>(), nearest.size());

  // Without --keep the per-pixel errors go.
  ASSERT_EQ(runCommand("scripts/eval_tables.py common " + out).exit_code, 0);
  EXPECT_FALSE(std::filesystem::exists(out + "/errors"));
  EXPECT_TRUE(std::filesystem::exists(out + "/radar_common.json"));

  // Errors of two different truths (another stride) cannot be compared: it fails naming them.
  for (const std::string stride : {"1", "2"}) {
    const auto r =
        runTool("evaluate_depth", "--vod-root " + scene + " --frames 0 --quiet " +
                                      "--model nearest --stride " + stride + " --save-errors " +
                                      out + "/errors/radar_s" + stride);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const auto bad = runCommand("scripts/eval_tables.py common " + out);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("differ in length"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("00000_errors.npy"), std::string::npos) << bad.output;
}
