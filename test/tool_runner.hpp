#pragma once
// Runs one of the package's command-line tools (from MMNVS_TOOL_DIR, the devel space) with a shell
// argument string and captures its exit code and combined output, for the tools' end-to-end tests.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace multimodal_nvs {
namespace test {

struct ToolResult {
  int exit_code;  // -1 when killed by a signal
  std::string output;
};

// Runs a shell command line; stderr goes into the output too.
inline ToolResult runCommand(const std::string& command_line) {
  const std::string command = command_line + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return {-1, "popen failed: " + command};
  std::string output;
  std::array<char, 512> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr)
    output += buffer.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

inline ToolResult runTool(const std::string& tool, const std::string& args) {
  return runCommand(std::string(MMNVS_TOOL_DIR) + "/" + tool + " " + args);
}

}  // namespace test
}  // namespace multimodal_nvs
