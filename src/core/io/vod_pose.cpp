#include "multimodal_nvs/core/io/vod_pose.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <utility>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace io {
namespace {

/// One entry of a pose file: key and, when the value is an array of numbers, those numbers.
struct PoseEntry {
  std::string key;
  bool numeric_array = false;
  std::vector<double> numbers;
};

/// A strict reader for the small JSON subset of pose files: a sequence of objects (JSON lines or
/// one object) whose values may be any JSON value; arrays of numbers are kept, the rest skipped.
/// Hand-written because the core depends on Eigen and OpenCV only.
class PoseJsonReader {
 public:
  PoseJsonReader(const std::string& text, const std::string& source)
      : text_(text), source_(source) {}

  std::vector<PoseEntry> readAll() {
    std::vector<PoseEntry> entries;
    skipSpace();
    if (pos_ >= text_.size()) fail("file is empty");
    while (pos_ < text_.size()) {
      readObject(entries);
      skipSpace();
    }
    return entries;
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < pos_ && i < text_.size(); ++i) {
      if (text_[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    throw InputError(source_ + ":" + std::to_string(line) + ":" + std::to_string(column) +
                     ": malformed pose JSON: " + reason);
  }

  void skipSpace() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' ||
                                   text_[pos_] == '\n' || text_[pos_] == '\r')) {
      ++pos_;
    }
  }

  void expect(char c) {
    skipSpace();
    if (pos_ >= text_.size() || text_[pos_] != c) {
      fail(std::string("expected '") + c + "'" +
           (pos_ < text_.size() ? std::string(", found '") + text_[pos_] + "'"
                                : std::string(" before end of file")));
    }
    ++pos_;
  }

  bool peek(char c) {
    skipSpace();
    return pos_ < text_.size() && text_[pos_] == c;
  }

  std::string readString() {
    expect('"');
    std::string out;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      if (text_[pos_] == '\\') {
        ++pos_;
        if (pos_ >= text_.size()) break;
      }
      out += text_[pos_++];
    }
    if (pos_ >= text_.size()) fail("unterminated string");
    ++pos_;
    return out;
  }

  double readNumber() {
    skipSpace();
    const char* begin = text_.c_str() + pos_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) fail("expected a number");
    pos_ += static_cast<std::size_t>(end - begin);
    return v;
  }

  bool startsNumber() {
    skipSpace();
    if (pos_ >= text_.size()) return false;
    const char c = text_[pos_];
    return c == '-' || c == '+' || (c >= '0' && c <= '9') || c == 'N' || c == 'I' || c == 'n' ||
           c == 'i';
  }

  void readLiteral() {
    skipSpace();
    for (const char* word : {"true", "false", "null"}) {
      if (text_.compare(pos_, std::char_traits<char>::length(word), word) == 0) {
        pos_ += std::char_traits<char>::length(word);
        return;
      }
    }
    fail("unexpected character");
  }

  /// Reads any value; when it is an array of numbers only, returns them through `numbers`.
  bool readValue(std::vector<double>* numbers) {
    skipSpace();
    if (pos_ >= text_.size()) fail("value missing before end of file");
    const char c = text_[pos_];
    if (c == '{') {
      std::vector<PoseEntry> ignored;
      readObject(ignored);
      return false;
    }
    if (c == '"') {
      readString();
      return false;
    }
    if (c == '[') {
      const NestingGuard guard(*this);
      ++pos_;
      bool all_numbers = true;
      if (peek(']')) {
        ++pos_;
        return false;
      }
      while (true) {
        if (startsNumber() && text_[pos_] != 'n') {
          const double v = readNumber();
          if (numbers != nullptr) numbers->push_back(v);
        } else {
          readValue(nullptr);
          all_numbers = false;
        }
        if (peek(',')) {
          ++pos_;
          continue;
        }
        expect(']');
        return all_numbers;
      }
    }
    if (startsNumber() && c != 'n') {
      readNumber();
      return false;
    }
    readLiteral();
    return false;
  }

  void readObject(std::vector<PoseEntry>& entries) {
    const NestingGuard guard(*this);
    expect('{');
    if (peek('}')) {
      ++pos_;
      return;
    }
    while (true) {
      PoseEntry entry;
      entry.key = readString();
      expect(':');
      entry.numeric_array = readValue(&entry.numbers);
      if (!entry.numeric_array) entry.numbers.clear();
      entries.push_back(std::move(entry));
      if (peek(',')) {
        ++pos_;
        continue;
      }
      expect('}');
      return;
    }
  }

  // Values nest by recursion: without a limit, a file of many '[' overflows the stack instead of
  // raising InputError. Pose files nest two levels; 64 leaves room for any metadata.
  static constexpr int kMaxNesting = 64;
  struct NestingGuard {
    explicit NestingGuard(PoseJsonReader& reader) : reader_(reader) {
      if (reader_.nesting_ == kMaxNesting) {
        reader_.fail("nested deeper than " + std::to_string(kMaxNesting) + " levels");
      }
      ++reader_.nesting_;
    }
    ~NestingGuard() { --reader_.nesting_; }
    NestingGuard(const NestingGuard&) = delete;
    NestingGuard& operator=(const NestingGuard&) = delete;
    PoseJsonReader& reader_;
  };

  const std::string& text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int nesting_ = 0;
};

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
  for (const PoseEntry& e : PoseJsonReader(text, source).readAll()) {
    if (e.numeric_array) keys.push_back(e.key);
  }
  return keys;
}

Eigen::Matrix4d parseVodPose(const std::string& text, const std::string& key,
                             const std::string& source) {
  const std::vector<PoseEntry> entries = PoseJsonReader(text, source).readAll();
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
  if (!in) throw InputError(path + ": cannot open pose file");
  std::ostringstream text;
  text << in.rdbuf();
  return parseVodPose(text.str(), key, path);
}

}  // namespace io
}  // namespace multimodal_nvs
