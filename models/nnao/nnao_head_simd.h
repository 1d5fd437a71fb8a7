#pragma once
// The NNAO network after layer 0's sums, on 16 pixels at once (screen_space/simd16.h):
// shared by the grid's exact and shader-style paths and the horizon path.
#include "models/nnao/nnao_weights.h"
#include "screen_space/simd16.h"

namespace nns::nnao::detail {

using namespace screen_space::simd;

// Layers 1..3 and the de-standardisation (NnaoWeights::head, same order of operations)
// on the 16 lanes at once, from the layer-0 sums h[k]: h[k] * scale + b0[k], plus the
// inputs' base where there is one (the horizon kind). Sky and tail lanes get 1.
// HS > 0: the hidden width known at compile time, so the activations stay in registers
// (with a runtime width they round-trip through the stack; docs/nnao.md, "Speed", has
// the measured difference); the same operations in the same order either way.
template <int HS = 0>
void finish_block(const NnaoWeights& m, const Block& b, const VF* h, float scale, bool scaled, float* out,
                  const VF* base = nullptr) {
  const int H = HS > 0 ? HS : m.hidden;
  auto prelu = [](VF x, float alpha, float beta) { return screen_space::simd::prelu(x, splat(alpha), splat(beta)); };
  VF a[HS > 0 ? HS : 64], c[HS > 0 ? HS : 64];
  for (int k = 0; k < H; ++k)
    a[k] = prelu((scaled ? h[k] * splat(scale) : h[k]) + splat(m.b0[size_t(k)]), m.alpha[0][size_t(k)],
                 m.beta[0][size_t(k)]);
  int n = H;
  for (int l = 0; l < 3; ++l) {
    const int outs = l == 2 ? 1 : H;
    for (int o = 0; o < outs; ++o) {
      VF s = splat(m.b[l][size_t(o)]);
      for (int i = 0; i < n; ++i) s = s + splat(m.w[l][size_t(o) * n + i]) * a[i];
      c[o] = prelu(s, m.alpha[l + 1][size_t(o)], m.beta[l + 1][size_t(o)]);
    }
    for (int o = 0; o < outs; ++o) a[o] = c[o];
    n = outs;
  }
  VF ao = a[0] * splat(m.target_std) + splat(m.target_mean);
  if (base) ao = ao + *base;
  ao = saturate(ao);
  store(out + b.i0, select(b.live, ao, splat(1.0f)), b.valid);
}

}  // namespace nns::nnao::detail
