#pragma once
// NNAO's exact form, one pixel at a time: the raw inputs (nnao_inputs.h, grid or
// horizon), layer 0 with the standardisation folded in (nnao_weights.h), the head, plus
// the inputs' base. It is the scalar reference the vectorised grid path of
// nnao_inference.h must match, and the horizon models' inference itself (their
// marches stop at the screen edge, so lanes would diverge). Rows run on the thread
// pool; every pixel is computed the same way whatever the thread count. Sky pixels get
// AO = 1.
#include <vector>

#include "core/thread_pool.h"
#include "models/nnao/nnao_inputs.h"
#include "models/nnao/nnao_weights.h"
#include "screen_space/gbuffer.h"

namespace nns::nnao {

inline void infer_exact_per_pixel(const NnaoWeights& m, const screen_space::GBuffer& g, float* out) {
  const int64_t F = m.features();
  const int H = m.hidden;
  parallel_for(
      g.height,
      [&](int64_t y0, int64_t y1) {
        std::vector<float> f(static_cast<size_t>(F));
        float h[64];
        for (int64_t y = y0; y < y1; ++y)
          for (int x = 0; x < g.width; ++x) {
            const int64_t i = y * g.width + x;
            if (g.sky(i)) {
              out[i] = 1;
              continue;
            }
            m.input.compute(g, x, int(y), f.data());
            for (int k = 0; k < H; ++k) {
              const float* wk = m.w0.data() + int64_t(k) * F;
              float s = 0;
              for (int64_t q = 0; q < F; ++q) s += wk[q] * f[size_t(q)];
              h[k] = s + m.b0[size_t(k)];
            }
            out[i] = m.head(h, m.input.base(f.data()));
          }
      },
      1);
}

}  // namespace nns::nnao
