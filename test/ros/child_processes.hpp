#pragma once
// Tools and rosbag run from the gtest-in-rostest programs: a command line to completion, or a
// child process in its own group (so that teardown can stop rosbag and its play binary).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace rostest_helpers {

/// Runs a command line through the shell; true on exit status 0.
inline bool run(const std::string& command) {
  const int status = std::system(command.c_str());
  return status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// Starts argv as a child process (PATH lookup) in its own process group; its pid, or -1.
inline pid_t spawn(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& a : argv)
    args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    execvp(args[0], args.data());
    _exit(127);
  }
  return pid;
}

}  // namespace rostest_helpers
