#pragma once
// The bits of a value as another type of the same size (C++20's std::bit_cast, for C++17).
#include <cstring>
#include <type_traits>

namespace multimodal_nvs {

template <class To, class From>
inline To bitCast(const From& from) {
  static_assert(sizeof(To) == sizeof(From), "bitCast needs types of the same size");
  static_assert(std::is_trivially_copyable_v<To> && std::is_trivially_copyable_v<From>,
                "bitCast needs trivially copyable types");
  To to;
  std::memcpy(&to, &from, sizeof to);
  return to;
}

}  // namespace multimodal_nvs
