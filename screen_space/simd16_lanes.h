#pragma once
// What every simd16 backend shares: sixteen lanes, and a mask as the bits of a uint32
// (bit l = lane l; only the low 16 bits are used), whatever the instruction set.
#include <cstdint>

namespace nns::screen_space::simd {

constexpr int kLanes = 16;
using Mask = uint32_t;
constexpr Mask kAll = 0xFFFFu;

}  // namespace nns::screen_space::simd
