#include "multimodal_nvs/core/common/json_text.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace multimodal_nvs {

std::string jsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  std::ostringstream s;
  s << std::setprecision(10) << value;
  return s.str();
}

std::string jsonEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += ' ';
      continue;
    }
    out += c;
  }
  return out;
}

}  // namespace multimodal_nvs
