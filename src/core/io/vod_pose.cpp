#include "multimodal_nvs/core/io/vod_pose.hpp"

#include <Eigen/Dense>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {
namespace {

using Json = nlohmann::ordered_json;

/// One entry of a pose file: key and, when the value is a non-empty array of numbers, those
/// numbers.
struct PoseEntry {
  std::string key;
  bool numeric_array = false;
  std::vector<double> numbers;
};

/// "source:line:column" of byte `offset` of `text`.
std::string positionOf(const std::string& text, std::size_t offset, const std::string& source) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return source + ":" + std::to_string(line) + ":" + std::to_string(column);
}

/// nlohmann's message without its "[json.exception...] parse error at line L, column C: " prefix
/// (the position is re-computed over the whole file, not the one object).
std::string reasonOf(const nlohmann::json::exception& e) {
  std::string what = e.what();
  const std::size_t bracket = what.find("] ");
  if (bracket != std::string::npos) what.erase(0, bracket + 2);
  const std::size_t colon = what.find(": ");
  if (what.rfind("parse error", 0) == 0 && colon != std::string::npos) what.erase(0, colon + 2);
  return what;
}

/// Pose files are a sequence of JSON objects (JSON lines, or one object over many lines), which
/// nlohmann's stream extraction reads one value at a time. Keys keep file order; a key repeated in
/// a later object wins, as it does within one object.
std::vector<PoseEntry> readEntries(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::vector<PoseEntry> entries;
  while (true) {
    in >> std::ws;
    if (in.peek() == std::char_traits<char>::eof()) break;
    const std::size_t start = static_cast<std::size_t>(in.tellg());
    if (in.peek() != '{') {
      throw InputError(positionOf(text, start, source) +
                       ": malformed pose JSON: expected an object ('{')");
    }
    Json object;
    try {
      in >> object;
    } catch (const nlohmann::json::parse_error& e) {
      const std::size_t at = start + (e.byte > 0 ? e.byte - 1 : 0);
      throw InputError(positionOf(text, at, source) + ": malformed pose JSON: " + reasonOf(e));
    } catch (const nlohmann::json::exception& e) {
      // E.g. out_of_range for a number beyond double ("1e999"); it has no position of its own.
      throw InputError(positionOf(text, start, source) + ": malformed pose JSON: " + reasonOf(e));
    }
    for (const auto& item : object.items()) {
      PoseEntry entry;
      entry.key = item.key();
      const Json& value = item.value();
      // Metadata may nest deeply; it is only looked at, never copied (copies recurse).
      entry.numeric_array = value.is_array() && !value.empty();
      if (entry.numeric_array) {
        for (const Json& element : value) {
          if (!element.is_number()) {
            entry.numeric_array = false;
            break;
          }
          entry.numbers.push_back(element.get<double>());
        }
      }
      if (!entry.numeric_array) entry.numbers.clear();
      entries.push_back(std::move(entry));
    }
  }
  if (entries.empty() && text.find('{') == std::string::npos) {
    throw InputError(source + ": malformed pose JSON: file is empty");
  }
  return entries;
}

void checkRigid(const Eigen::Matrix4d& m, const std::string& where) {
  if (std::abs(m(3, 0)) > 1e-9 || std::abs(m(3, 1)) > 1e-9 || std::abs(m(3, 2)) > 1e-9 ||
      std::abs(m(3, 3) - 1.0) > 1e-9) {
    throw InputError(where + ": last row must be 0 0 0 1");
  }
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  // VoD poses are orthonormal to ~1e-15; 1e-4 accepts rounding in hand-written files but rejects
  // scaled or sheared matrices, which SLERP would silently turn into something else.
  const double error = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (error > 1e-4 || r.determinant() < 0.0) {
    throw InputError(where +
                     ": rotation part is not orthonormal with determinant +1 (|R^T R - I| = " +
                     std::to_string(error) + ")");
  }
}

}  // namespace

std::vector<std::string> vodPoseKeys(const std::string& text, const std::string& source) {
  std::vector<std::string> keys;
  for (const PoseEntry& e : readEntries(text, source)) {
    if (e.numeric_array) keys.push_back(e.key);
  }
  return keys;
}

Eigen::Matrix4d parseVodPose(const std::string& text, const std::string& key,
                             const std::string& source) {
  const std::vector<PoseEntry> entries = readEntries(text, source);
  const PoseEntry* found = nullptr;
  std::string present;
  for (const PoseEntry& e : entries) {
    present += (present.empty() ? "" : ", ") + e.key;
    if (e.key == key) found = &e;
  }
  if (found == nullptr) {
    throw InputError(source + ": pose key '" + key + "' not found (keys present: " +
                     (present.empty() ? std::string("none") : present) + ")");
  }
  const std::string where = source + ": '" + key + "'";
  if (!found->numeric_array || found->numbers.size() != 16) {
    throw InputError(where + " must be an array of 16 numbers (row-major 4x4)" +
                     (found->numeric_array ? ", found " + std::to_string(found->numbers.size())
                                           : std::string()));
  }
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) {
    const double v = found->numbers[static_cast<std::size_t>(i)];
    if (!std::isfinite(v))
      throw InputError(where + ": element " + std::to_string(i) + " is not finite");
    m(i / 4, i % 4) = v;
  }
  checkRigid(m, where);
  return m;
}

Eigen::Matrix4d readVodPose(const std::string& path, const std::string& key) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open pose file (" + std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  return parseVodPose(text.str(), key, path);
}

}  // namespace io
}  // namespace multimodal_nvs
