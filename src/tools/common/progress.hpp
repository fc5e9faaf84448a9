#pragma once
// Progress of a tool over many items (frames), on stderr so that stdout stays JSON: a bar redrawn
// in place on a terminal, one plain line per item when stderr is a pipe or a file (logs, CI), and a
// throughput figure at the end. One helper for every tool that loops over frames.
#include <chrono>
#include <string>

namespace multimodal_nvs {
namespace cli {

class Progress {
 public:
  /// `quiet`: print nothing, not even the summary.
  Progress(std::string tool, int total, std::string unit = "frames", bool quiet = false);

  /// One item done; `label` names it in the plain-line form (e.g. the frame number).
  void step(const std::string& label = std::string());

  /// "tool: 16 frames in 12.3 s (1.30 frames/s, 769 ms per frame)". Called once, at the end.
  void finish();

  double seconds() const;
  int done() const { return done_; }

 private:
  std::string tool_, unit_;
  int total_, done_ = 0;
  bool quiet_, terminal_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace cli
}  // namespace multimodal_nvs
