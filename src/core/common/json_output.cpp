#include "multimodal_nvs/core/common/json_output.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace json {

Json number(double v, int digits) {
  if (!std::isfinite(v)) return nullptr;
  std::ostringstream text;
  text << std::setprecision(digits) << v;
  const double rounded = std::stod(text.str());
  if (rounded == std::floor(rounded) && std::abs(rounded) < 9e15) {
    return static_cast<std::int64_t>(rounded);
  }
  return rounded;
}

namespace {

void appendScalar(const Json& value, std::string& out) {
  out += value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

void appendOneLine(const Json& value, std::string& out) {
  if (value.is_object()) {
    out += '{';
    bool first = true;
    for (const auto& item : value.items()) {
      if (!first) out += ", ";
      first = false;
      appendScalar(Json(item.key()), out);
      out += ": ";
      appendOneLine(item.value(), out);
    }
    out += '}';
  } else if (value.is_array()) {
    out += '[';
    for (std::size_t i = 0; i < value.size(); ++i) {
      if (i > 0) out += ", ";
      appendOneLine(value[i], out);
    }
    out += ']';
  } else {
    appendScalar(value, out);
  }
}

bool isArrayOfObjects(const Json& value) {
  return value.is_array() && !value.empty() && value.front().is_object();
}

}  // namespace

std::string oneLine(const Json& value) {
  std::string out;
  appendOneLine(value, out);
  return out;
}

std::string document(const Json& value) {
  if (!value.is_object()) return oneLine(value) + "\n";
  std::string out = "{\n";
  bool first = true;
  for (const auto& item : value.items()) {
    if (!first) out += ",\n";
    first = false;
    out += "  ";
    appendScalar(Json(item.key()), out);
    out += ": ";
    if (isArrayOfObjects(item.value())) {
      out += "[\n";
      const Json& array = item.value();
      for (std::size_t i = 0; i < array.size(); ++i) {
        out += "    ";
        appendOneLine(array[i], out);
        out += i + 1 < array.size() ? ",\n" : "\n";
      }
      out += "  ]";
    } else {
      appendOneLine(item.value(), out);
    }
  }
  out += "\n}\n";
  return out;
}

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  out << text;
  out.flush();
  if (!out) throw InputError(path + ": cannot write (" + std::strerror(errno) + ")");
}

}  // namespace json
}  // namespace multimodal_nvs
