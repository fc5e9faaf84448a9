// rviz as a user opens it (demo.launch gui:=true, rviz/multimodal_nvs.rviz) on a virtual 1600x1000
// screen: scripts/rviz_screenshot.sh plays a short synthetic bag, takes a screenshot once the depth
// nodelet's colour images have arrived, and prints the coloured share of each image panel; the
// depth and standard-deviation panels must not be blank. Needs the sourced devel space
// (scripts/run_tests.sh) and Debian's xvfb and imagemagick.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>
#include <string>

#include "tool_runner.hpp"

namespace multimodal_nvs {
namespace test {
namespace {

namespace fs = std::filesystem;

TEST(RvizScreenshot, DepthAndUncertaintyPanelsShowImages) {
  char pattern[] = "/tmp/mmnvs_rviz_XXXXXX";
  ASSERT_NE(mkdtemp(pattern), nullptr) << std::strerror(errno);
  const std::string dir = pattern;
  ToolResult result = runTool("make_synthetic_scene", "--output " + dir +
                                                          "/scene --scale 0.25 --num-frames 6 "
                                                          "--threads 1 --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  result =
      runTool("vod_to_bag", "--vod-root " + dir + "/scene --output " + dir + "/scene.bag --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.output;

  result = runCommand(std::string(MMNVS_SOURCE_DIR) + "/scripts/rviz_screenshot.sh " + dir + "/scene.bag " + dir + "/rviz.png");
  std::printf("%s", result.output.c_str());  // the shares, in the test log
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir + "/rviz.png"));
  for (const char* panel : {"depth", "std. deviation"}) {
    const std::regex line(std::string("rviz panel ") + panel + ": coloured share ([0-9.]+)");
    std::smatch match;
    ASSERT_TRUE(std::regex_search(result.output, match, line)) << panel << "\n" << result.output;
    EXPECT_GE(std::stod(match[1]), 0.3) << panel;
  }
  std::error_code ignored;
  fs::remove_all(dir, ignored);
}

}  // namespace
}  // namespace test
}  // namespace multimodal_nvs
