#pragma once
// JSON output of the tools and the renderer's exports on nlohmann-json (Debian's
// nlohmann-json3-dev): values are built as ordered_json (keys in insertion order); the text layout
// is Python's json.dumps style, which nlohmann's dump() cannot produce (it has no ", " / ": "
// separators), so that the figures the tools printed before keep their exact text and the scripts
// and people diffing them see no churn.
#include <nlohmann/json.hpp>
#include <string>

namespace multimodal_nvs {
namespace json {

using Json = nlohmann::ordered_json;

/// `v` with `digits` significant digits (what the tools have always printed), an integer when it is
/// integral, null when it is not finite (JSON has no NaN or infinity).
Json number(double v, int digits = 10);

/// One line: `{"a": 1, "b": [2, 3]}`. Strings are escaped by nlohmann (control characters as
/// \u00XX, invalid UTF-8 replaced by U+FFFD).
std::string oneLine(const Json& value);

/// A file: each top-level member on its own line, and an array of objects one element per line.
std::string document(const Json& value);

/// Writes `text` to `path`; throws InputError with the OS reason when it cannot.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace json
}  // namespace multimodal_nvs
