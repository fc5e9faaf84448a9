#pragma once
// Vectors aligned for Eigen's widest packets, so vectorised maths gives the same bits everywhere.
#include <Eigen/Core>
#include <vector>

namespace multimodal_nvs {

/// A vector aligned for Eigen's widest packets. Eigen processes the unaligned head of a Map with
/// scalar code (scalar exp differs from its vectorised exp in the last bit), so with plain
/// std::vector (16-byte aligned) a result could depend on where the allocator put the buffer --
/// that is, on which thread ran. Every buffer that Eigen exponentiates uses this type.
template <typename T>
using SimdVector = std::vector<T, Eigen::aligned_allocator<T>>;

}  // namespace multimodal_nvs
