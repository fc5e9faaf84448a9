#pragma once
// The two pieces of JSON text the tools and the renderer's exports write by hand (their JSON is
// small and flat; no JSON library is worth a dependency for it).
#include <string>

namespace multimodal_nvs {

/// Ten significant digits; "null" for NaN and infinities (JSON has no literal for them).
std::string jsonNumber(double value);

/// `text` as the inside of a JSON string: quote and backslash escaped, control characters as
/// spaces.
std::string jsonEscape(const std::string& text);

}  // namespace multimodal_nvs
