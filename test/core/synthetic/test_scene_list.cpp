// eval/synthetic_scenes.tsv, the fixed dev / validation split of the evaluation's synthetic scenes:
// it parses, both splits are there and each spans the varied parameters, and make_synthetic_scene
// accepts every row's arguments.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tool_runner.hpp"

namespace {

struct SceneRow {
  std::string name, split, args;
  std::map<std::string, std::string> options;  ///< --key value pairs of args
};

/// Rows of the list (the tests run from the repository root); '#' lines are comments.
std::vector<SceneRow> readSceneList(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path << " cannot be read";
  std::vector<SceneRow> rows;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> columns;
    std::stringstream ss(line);
    std::string column;
    while (std::getline(ss, column, '\t'))
      columns.push_back(column);
    EXPECT_EQ(columns.size(), 3u) << path << ":" << number << ": name, split, arguments";
    if (columns.size() != 3) continue;
    SceneRow row{columns[0], columns[1], columns[2], {}};
    std::stringstream words(row.args);
    std::string key, value;
    while (words >> key) {
      EXPECT_EQ(key.rfind("--", 0), 0u) << path << ":" << number << ": '" << key << "'";
      EXPECT_TRUE(static_cast<bool>(words >> value)) << path << ":" << number << ": " << key;
      row.options[key.substr(2)] = value;
    }
    rows.push_back(row);
  }
  return rows;
}

double option(const SceneRow& row, const std::string& key, double fallback) {
  const auto it = row.options.find(key);
  return it == row.options.end() ? fallback : std::stod(it->second);
}

const char* kSceneList = "eval/synthetic_scenes.tsv";

}  // namespace

TEST(SyntheticSceneList, HasBothSplitsAndEachSpansTheVariedParameters) {
  const std::vector<SceneRow> rows = readSceneList(kSceneList);
  ASSERT_GE(rows.size(), 12u);
  std::set<std::string> names;
  std::map<std::string, std::vector<const SceneRow*>> by_split;
  for (const SceneRow& row : rows) {
    EXPECT_TRUE(names.insert(row.name).second) << "scene name twice: " << row.name;
    EXPECT_TRUE(row.split == "dev" || row.split == "validation") << row.name << ": " << row.split;
    EXPECT_EQ(row.options.count("seed"), 1u) << row.name << " has no --seed";
    for (const char* fixed : {"frames", "scale", "output"}) {
      EXPECT_EQ(row.options.count(fixed), 0u) << row.name << ": eval.sh sets --" << fixed;
    }
    by_split[row.split].push_back(&row);
  }
  ASSERT_EQ(by_split.size(), 2u);
  // About half each, and no seed in both (validation scenes are streets never tuned on).
  const std::size_t dev = by_split["dev"].size(), validation = by_split["validation"].size();
  EXPECT_LE(std::max(dev, validation), 2 * std::min(dev, validation));
  std::set<std::string> dev_seeds;
  for (const SceneRow* row : by_split["dev"])
    dev_seeds.insert(row->options.at("seed"));
  for (const SceneRow* row : by_split["validation"]) {
    EXPECT_EQ(dev_seeds.count(row->options.at("seed")), 0u) << row->name << " reuses a dev seed";
  }
  for (const auto& [split, members] : by_split) {
    SCOPED_TRACE(split);
    double height_min = 1e9, height_max = -1e9, pitch_min = 1e9, pitch_max = -1e9;
    std::set<int> beams;
    int with_people = 0, with_vehicles = 0, with_poles = 0, sparse_radar = 0, dense_radar = 0;
    for (const SceneRow* row : members) {
      const double height = option(*row, "camera-height", 1.3);
      const double pitch = option(*row, "camera-pitch", 0.0);
      height_min = std::min(height_min, height);
      height_max = std::max(height_max, height);
      pitch_min = std::min(pitch_min, pitch);
      pitch_max = std::max(pitch_max, pitch);
      beams.insert(static_cast<int>(option(*row, "lidar-beams", 64)));
      with_people += option(*row, "pedestrians", 0) > 0;
      with_vehicles += option(*row, "vehicles", 0) > 0;
      with_poles += option(*row, "poles", 0) > 0;
      sparse_radar += option(*row, "radar-candidates", 1600) < 1000;
      dense_radar += option(*row, "radar-candidates", 1600) > 2000;
    }
    EXPECT_LE(height_min, 1.3);
    EXPECT_GE(height_max, 2.0);
    EXPECT_LE(pitch_min, -3.0);
    EXPECT_GE(pitch_max, 6.0);
    EXPECT_EQ(beams, (std::set<int>{16, 32, 64}));
    EXPECT_GT(with_people, 0);
    EXPECT_GT(with_vehicles, 0);
    EXPECT_GT(with_poles, 0);
    EXPECT_GT(sparse_radar, 0);
    EXPECT_GT(dense_radar, 0);
  }
}

TEST(SyntheticSceneList, MakeSyntheticSceneAcceptsEveryRow) {
  const std::string root = ::testing::TempDir() + "scene_list";
  for (const SceneRow& row : readSceneList(kSceneList)) {
    std::filesystem::remove_all(root);
    const auto r = multimodal_nvs::test::runTool(
        "make_synthetic_scene", "--output " + root + " --scale 0.05 --frames 1 --quiet " +
                                    "--lidar-azimuth-step 2 " + row.args);
    EXPECT_EQ(r.exit_code, 0) << row.name << ": " << row.args << "\n" << r.output;
  }
}
