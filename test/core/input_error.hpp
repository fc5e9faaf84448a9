#pragma once
// The message of the InputError a reader throws, for tests of bad input.
#include <string>

#include "multimodal_nvs/core/common/errors.hpp"

namespace multimodal_nvs {
namespace test {

/// What `f` throws as InputError, or "" if it returns normally.
template <typename F>
std::string inputErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace test
}  // namespace multimodal_nvs
