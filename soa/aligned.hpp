// 32-byte aligned storage for structure-of-arrays data.
#pragma once

#include "core/memory.hpp"
#include "core/num.hpp"

#include <vector>

namespace rb {
template <class T>
using avec = std::vector<T, BigAllocator<T, kSimdAlign>>;  // large ones on huge pages (core/memory.hpp)
inline constexpr std::size_t kPadLanes = 8;  // every SoA array is padded to a multiple of this
inline std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }
}  // namespace rb
