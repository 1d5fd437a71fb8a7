#pragma once
// simd16's portable backend (include screen_space/simd16.h, not this): plain loops over
// 16 floats, which the compiler vectorises as far as the target allows. It is the
// reference every other backend matches lane for lane (tests/screen_space/test_simd16.cpp).
#include <cmath>
#include <cstdint>

#include "screen_space/simd16_lanes.h"

namespace nns::ao::simd {

constexpr const char* kBackend = "generic";

struct VF {
  float v[kLanes];
};
struct VI {
  int32_t v[kLanes];
};
#define NNS_LANES for (int l = 0; l < kLanes; ++l)
inline VF splat(float a) { VF r; NNS_LANES r.v[l] = a; return r; }
inline VI splat_i(int a) { VI r; NNS_LANES r.v[l] = a; return r; }
inline VF load(const float* p) { VF r; NNS_LANES r.v[l] = p[l]; return r; }
inline VF load(const float* p, Mask m, float fill) { VF r; NNS_LANES r.v[l] = (m >> l & 1) ? p[l] : fill; return r; }
inline void store(float* p, VF a, Mask m) { NNS_LANES if (m >> l & 1) p[l] = a.v[l]; }
inline VF operator+(VF a, VF b) { NNS_LANES a.v[l] += b.v[l]; return a; }
inline VF operator-(VF a, VF b) { NNS_LANES a.v[l] -= b.v[l]; return a; }
inline VF operator*(VF a, VF b) { NNS_LANES a.v[l] *= b.v[l]; return a; }
inline VF operator/(VF a, VF b) { NNS_LANES a.v[l] /= b.v[l]; return a; }
inline VF sqrt(VF a) { NNS_LANES a.v[l] = std::sqrt(a.v[l]); return a; }
inline VF min(VF a, VF b) { NNS_LANES a.v[l] = b.v[l] < a.v[l] ? b.v[l] : a.v[l]; return a; }
inline VF max(VF a, VF b) { NNS_LANES a.v[l] = b.v[l] > a.v[l] ? b.v[l] : a.v[l]; return a; }
inline VF abs(VF a) { NNS_LANES a.v[l] = std::fabs(a.v[l]); return a; }
inline VF floor(VF a) { NNS_LANES a.v[l] = std::floor(a.v[l]); return a; }
inline VI to_int(VF a) { VI r; NNS_LANES r.v[l] = int32_t(a.v[l]); return r; }
inline VI floor_to_int(VF a) { VI r; NNS_LANES r.v[l] = int32_t(std::floor(a.v[l])); return r; }
inline VF to_float(VI a) { VF r; NNS_LANES r.v[l] = float(a.v[l]); return r; }
inline VI operator+(VI a, VI b) { NNS_LANES a.v[l] += b.v[l]; return a; }
inline VI operator*(VI a, VI b) { NNS_LANES a.v[l] *= b.v[l]; return a; }
inline VI clamp(VI a, int lo, int hi) { NNS_LANES a.v[l] = a.v[l] < lo ? lo : (a.v[l] > hi ? hi : a.v[l]); return a; }
inline VI lane_index() { VI r; NNS_LANES r.v[l] = l; return r; }
inline Mask lt(VF a, VF b) { Mask m = 0; NNS_LANES m |= Mask(a.v[l] < b.v[l]) << l; return m; }
inline Mask le(VF a, VF b) { Mask m = 0; NNS_LANES m |= Mask(a.v[l] <= b.v[l]) << l; return m; }
inline Mask gt(VF a, VF b) { Mask m = 0; NNS_LANES m |= Mask(a.v[l] > b.v[l]) << l; return m; }
inline Mask ge(VF a, VF b) { Mask m = 0; NNS_LANES m |= Mask(a.v[l] >= b.v[l]) << l; return m; }
inline VF select(Mask m, VF a, VF b) { NNS_LANES a.v[l] = (m >> l & 1) ? a.v[l] : b.v[l]; return a; }
inline VF gather(const float* base, VI idx, Mask m, float fill) {
  VF r; NNS_LANES r.v[l] = (m >> l & 1) ? base[idx.v[l]] : fill; return r;
}
inline VF scale2(VF a, VF n) { NNS_LANES a.v[l] = std::ldexp(a.v[l], int(n.v[l])); return a; }
// A per-lane choice, not a bit mask and a blend: the compiler vectorises it (with
// select(gt(..)) the portable head built and tested a mask bit by bit).
inline VF prelu(VF x, VF alpha, VF beta) {
  NNS_LANES x.v[l] = x.v[l] > 0 ? beta.v[l] * x.v[l] : alpha.v[l] * x.v[l];
  return x;
}
#undef NNS_LANES

}  // namespace nns::ao::simd
