#pragma once
// InputError: the one exception for unusable input; it names the source and the reason.
#include <stdexcept>
#include <string>

namespace multimodal_nvs {

/// Raised for input that cannot be used (bad file, bad calibration, bad parameter). The message
/// always names the offending source (file, topic or parameter) and the reason.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace multimodal_nvs
