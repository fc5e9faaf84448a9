// NumPy .npy arrays (io::parseNpy) and their conversion to float (NpyArray::asFloat).
#include "fuzz_input.hpp"
#include "multimodal_nvs/core/common/errors.hpp"
#include "multimodal_nvs/core/io/npy.hpp"

namespace io = multimodal_nvs::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  io::NpyArray array;
  try {
    array = io::parseNpy(bytes, "fuzz");
  } catch (const multimodal_nvs::InputError&) {
    return 0;
  }
  const std::size_t count = array.elementCount();
  MMNVS_FUZZ_CHECK(!array.dtype.empty());
  MMNVS_FUZZ_CHECK(array.data.size() <= size);
  // Every supported dtype ('<f4', '|u1', ...) ends with its item size.
  MMNVS_FUZZ_CHECK(array.data.size() == count * std::size_t(array.dtype.back() - '0'));
  const std::vector<float> values = array.asFloat();
  MMNVS_FUZZ_CHECK(values.size() == count);
  return 0;
}
