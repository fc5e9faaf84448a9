// The tools as a ROS user starts them: `rosrun multimodal_nvs <tool>` after sourcing the devel
// space (run_tests.sh sources it). Debian's rosrun skips every executable below <package>/build/,
// so this fails if the devel space moves back inside build/ (scripts/devel_dir.sh), and rosrun
// stops to ask "please pick one" when it finds a second copy of a tool anywhere in the package.
#include <gtest/gtest.h>

#include <string>

#include "tool_runner.hpp"

namespace multimodal_nvs {
namespace test {
namespace {

ToolResult rosrun(const std::string& tool, const std::string& args) {
  // stdin from /dev/null: an ambiguous rosrun then fails instead of waiting for a choice.
  return runCommand("rosrun multimodal_nvs " + tool + " " + args + " < /dev/null");
}

// One ROS-free tool and one that links rosbag (each rosrun walks the package tree: about 3 s).
TEST(Rosrun, FindsToolsExactlyOnce) {
  for (const char* tool : {"complete_depth", "vod_to_bag"}) {
    const ToolResult result = rosrun(tool, "--help");
    EXPECT_EQ(result.exit_code, 0) << tool << ":\n" << result.output;
    EXPECT_EQ(result.output.find("[rosrun]"), std::string::npos) << tool << ":\n" << result.output;
    EXPECT_NE(result.output.find("--"), std::string::npos) << tool << " printed no options:\n"
                                                           << result.output;
  }
}

TEST(Rosrun, FindsTheStandaloneNode) {
  for (const char* node : {"depth_completion_node"}) {
    // Without a master the node exits non-zero; rosrun has found it when it says nothing itself.
    const ToolResult result = runCommand(
        "ROS_MASTER_URI=http://127.0.0.1:1 timeout 2 rosrun "
        "multimodal_nvs " +
        std::string(node) + " __name:=probe < /dev/null");
    EXPECT_EQ(result.output.find("[rosrun]"), std::string::npos) << node << ":\n" << result.output;
  }
}

TEST(Rosrun, ReportsAMissingTool) {
  const ToolResult result = rosrun("no_such_tool", "");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("Couldn't find executable named no_such_tool"), std::string::npos)
      << result.output;
}

}  // namespace
}  // namespace test
}  // namespace multimodal_nvs
