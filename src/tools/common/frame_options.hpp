#pragma once
// Frame selection, the same in every tool: `--frames` takes numbers and inclusive ranges separated
// by commas (`549,1047`, `8350-8365`, `0-3,8`), leading zeros optional; `--frames-file` takes one
// such item per line (`#` starts a comment); `--shard i/N` keeps every N-th frame of the list,
// starting at index i, so that a scheduler can spread a dataset over machines.
#include <string>
#include <vector>

#include "cli.hpp"

namespace multimodal_nvs {
namespace cli {

struct FrameOptions {
  std::string frames, frames_file, shard = "0/1";
};

/// Declares --frames and --frames-file (and --shard when `with_shard`) in `group`.
void declareFrameOptions(CLI::App& app, FrameOptions& options, const std::string& group,
                         const std::string& frames_help, bool with_shard);

/// The frames of a --frames list, in the order given. Throws UsageError naming --frames.
std::vector<int> parseFrameList(const std::string& text);

/// Whether a frame list was given (--frames or --frames-file).
bool framesGiven(const FrameOptions& options);

/// The selected frames: exactly one of --frames / --frames-file, then the shard. Throws
/// UsageError, or InputError when the frame file cannot be read (with the OS reason).
std::vector<int> selectedFrames(const FrameOptions& options);

struct Shard {
  int index = 0, count = 1;
};
Shard parseShard(const std::string& text);

}  // namespace cli
}  // namespace multimodal_nvs
