#include "frame_options.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/vod_layout.hpp"

namespace multimodal_nvs {
namespace cli {
namespace {

int frameNumber(const std::string& text, const std::string& item) {
  try {
    return io::parseFrameNumber(text);
  } catch (const std::exception& e) {
    throw UsageError("--frames: '" + item + "': " + e.what());
  }
}

/// Strict non-negative integer (the whole text), for --shard.
bool parseIndex(const std::string& text, int& value) {
  if (text.empty() || text.size() > 9) return false;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
  }
  value = std::stoi(text);
  return true;
}

}  // namespace

void declareFrameOptions(CLI::App& app, FrameOptions& options, const std::string& group,
                         const std::string& frames_help, bool with_shard) {
  app.add_option("--frames", options.frames, frames_help)->group(group);
  app.add_option("--frames-file", options.frames_file,
                 "file with the same items as --frames, one per line ('#' starts a comment)")
      ->group(group);
  if (with_shard) {
    app.add_option("--shard", options.shard,
                   "i/N: only frames whose index in the list is i modulo N")
        ->group(group);
  }
}

std::vector<int> parseFrameList(const std::string& text) {
  std::vector<int> frames;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t\r") + 1);
    if (item.empty()) continue;
    const std::size_t dash = item.find('-', 1);
    if (dash == std::string::npos) {
      frames.push_back(frameNumber(item, item));
      continue;
    }
    const int a = frameNumber(item.substr(0, dash), item);
    const int b = frameNumber(item.substr(dash + 1), item);
    if (b < a) throw UsageError("--frames: range '" + item + "' needs A <= B");
    for (int f = a; f <= b; ++f)
      frames.push_back(f);
  }
  if (frames.empty()) throw UsageError("--frames: no frame in '" + text + "'");
  return frames;
}

bool framesGiven(const FrameOptions& options) {
  return !options.frames.empty() || !options.frames_file.empty();
}

std::vector<int> selectedFrames(const FrameOptions& options) {
  if (options.frames.empty() == options.frames_file.empty()) {
    throw UsageError("give exactly one of --frames LIST or --frames-file FILE");
  }
  std::vector<int> all;
  if (!options.frames.empty()) {
    all = parseFrameList(options.frames);
  } else {
    const std::string& path = options.frames_file;
    std::ifstream in(path);
    if (!in) {
      throw InputError(path + ": cannot open frame list (" + std::strerror(errno) + ")");
    }
    std::string line, joined;
    while (std::getline(in, line)) {
      const std::size_t hash = line.find('#');
      if (hash != std::string::npos) line.erase(hash);
      if (line.find_first_not_of(" \t\r") != std::string::npos) joined += line + ",";
    }
    if (joined.empty()) throw InputError(path + ": no frame numbers");
    all = parseFrameList(joined);
  }
  const Shard shard = parseShard(options.shard);
  std::vector<int> frames;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (static_cast<int>(i % static_cast<std::size_t>(shard.count)) == shard.index) {
      frames.push_back(all[i]);
    }
  }
  return frames;
}

Shard parseShard(const std::string& text) {
  Shard s;
  const std::size_t slash = text.find('/');
  const bool ok = slash != std::string::npos && parseIndex(text.substr(0, slash), s.index) &&
                  parseIndex(text.substr(slash + 1), s.count);
  if (!ok || s.count < 1 || s.index >= s.count) {
    throw UsageError("--shard must be i/N with 0 <= i < N, got '" + text + "'");
  }
  return s;
}

}  // namespace cli
}  // namespace multimodal_nvs
