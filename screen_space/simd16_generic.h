#pragma once
// simd16's portable backend (include screen_space/simd16.h, not this): GCC's vector
// extension on 16 floats, lowered to whatever the target has (two ymm halves, four xmm
// quarters), and plain loops where the extension has no operator (masks, sqrt, gathers).
// The arithmetic is vector arithmetic for the same reason the other backends' is: GCC
// decides where a * b + c becomes one FMA on the vector statements it sees, and the
// intrinsics of simd16_avx2.h and simd16_avx512.h are such statements too. With plain
// loops over float arrays (this backend before) other products were fused: against the
// AVX2 backend HBAO, GTAO, Alchemy and the grid NNAO came out up to 6.6e-7 apart in up
// to 43% of their pixels (screen_space.backends_agree); now only where inlining differs.
// Operation by operation the results are the other backends' lane for lane
// (tests/screen_space/test_simd16.cpp).
#include <cmath>
#include <cstdint>

#include "screen_space/simd16_lanes.h"

namespace nns::screen_space::simd {

constexpr const char* kBackend = "generic";

// 16-byte aligned: a 64-byte aligned argument draws GCC's ABI note in every file.
typedef float Floats16 __attribute__((vector_size(64), aligned(16)));
typedef int32_t Ints16 __attribute__((vector_size(64), aligned(16)));
typedef uint32_t Uints16 __attribute__((vector_size(64), aligned(16)));

struct VF {
  Floats16 v;
};
struct VI {
  Ints16 v;
};

namespace generic {
// Lane l all ones when bit l of m is set (a VI, not an Ints16: a bare 64-byte vector
// returned by value draws GCC's ABI note on targets without AVX-512).
inline VI lanes(Mask m) {
  const Ints16 bit = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768};
  return {((Ints16{} + int32_t(m & kAll)) & bit) != 0};
}
inline Mask bits(const VI& c) {
  Mask m = 0;
  for (int l = 0; l < kLanes; ++l) m |= Mask(c.v[l] & 1) << l;
  return m;
}
}  // namespace generic

#define NNS_LANES for (int l = 0; l < kLanes; ++l)
inline VF splat(float a) {
  VF r;
  NNS_LANES r.v[l] = a;
  return r;
}
inline VI splat_i(int a) {
  VI r;
  NNS_LANES r.v[l] = a;
  return r;
}
inline VF load(const float* p) {
  VF r;
  __builtin_memcpy(&r.v, p, sizeof r.v);
  return r;
}
// Lanes outside m read `fill` and touch no memory.
inline VF load(const float* p, Mask m, float fill) {
  VF r;
  NNS_LANES r.v[l] = (m >> l & 1) ? p[l] : fill;
  return r;
}
inline void store(float* p, VF a, Mask m) {
  if ((m & kAll) == kAll) __builtin_memcpy(p, &a.v, sizeof a.v);
  else NNS_LANES if (m >> l & 1) p[l] = a.v[l];
}
inline VF operator+(VF a, VF b) { return {a.v + b.v}; }
inline VF operator-(VF a, VF b) { return {a.v - b.v}; }
inline VF operator*(VF a, VF b) { return {a.v * b.v}; }
inline VF operator/(VF a, VF b) { return {a.v / b.v}; }
inline VF sqrt(VF a) {
  NNS_LANES a.v[l] = std::sqrt(a.v[l]);
  return a;
}
inline VF min(VF a, VF b) { return {b.v < a.v ? b.v : a.v}; }
inline VF max(VF a, VF b) { return {b.v > a.v ? b.v : a.v}; }
inline VF abs(VF a) { return {(Floats16)((Ints16)a.v & 0x7FFFFFFF)}; }
inline VF floor(VF a) {
  NNS_LANES a.v[l] = std::floor(a.v[l]);
  return a;
}
// Out of range and NaN: INT_MIN, what the x86 conversion gives (C++ leaves it undefined).
inline VI to_int(VF a) { return {__builtin_convertvector(a.v, Ints16)}; }
inline VI floor_to_int(VF a) { return to_int(floor(a)); }
inline VF to_float(VI a) { return {__builtin_convertvector(a.v, Floats16)}; }
// Wrapping, as the hardware's: in unsigned lanes, where C++ defines it.
inline VI operator+(VI a, VI b) { return {(Ints16)((Uints16)a.v + (Uints16)b.v)}; }
inline VI operator*(VI a, VI b) { return {(Ints16)((Uints16)a.v * (Uints16)b.v)}; }
inline VI clamp(VI a, int lo, int hi) {
  const Ints16 l = a.v < lo ? Ints16{} + lo : a.v;
  return {l > hi ? Ints16{} + hi : l};
}
inline VI lane_index() { return {Ints16{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}}; }
inline Mask lt(VF a, VF b) { return generic::bits({a.v < b.v}); }
inline Mask le(VF a, VF b) { return generic::bits({a.v <= b.v}); }
inline Mask gt(VF a, VF b) { return generic::bits({a.v > b.v}); }
inline Mask ge(VF a, VF b) { return generic::bits({a.v >= b.v}); }
inline VF select(Mask m, VF a, VF b) { return {generic::lanes(m).v ? a.v : b.v}; }
inline VF gather(const float* base, VI idx, Mask m, float fill) {
  VF r;
  NNS_LANES r.v[l] = (m >> l & 1) ? base[idx.v[l]] : fill;
  return r;
}
inline VF scale2(VF a, VF n) {
  NNS_LANES a.v[l] = std::ldexp(a.v[l], int(n.v[l]));
  return a;
}
inline VF scale2_normal(VF a, VF n) { return scale2(a, n); }  // n in [-126, 127]
inline VF prelu(VF x, VF alpha, VF beta) { return {x.v > 0 ? beta.v * x.v : alpha.v * x.v}; }
#undef NNS_LANES

}  // namespace nns::screen_space::simd
