#pragma once
// NNAO's depth- and normal-aware blur as GLSL (nnao_inference.h, bilateral_blur): one
// 5-tap pass along uStep; draw it twice, (1, 0) then (0, 1), as the CPU does. Taps are
// weighted by a Gaussian (sigma 1.5 px) times exp(-(dz / (depth r))^2) times
// max(0, n.n')^power (the model's BlurEdges, nnao_weights.h; power by squaring in the
// CPU's order), so it does not average across a depth jump or a sharp crease. Both
// model kinds end with it (the grid's noise, the horizon model's flicker: docs/nnao.md).
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "runs/ao/nnao_glsl.h"

namespace nns::runs {

// `pairs`: how many times the engine draws the (1, 0), (0, 1) pair, each on the last
// one's result (NnaoWeights::blur_passes); written as NNAO_BLUR_PAIRS for the host.
inline std::string glsl_blur_pass(int pairs = 1, const nnao::BlurEdges& e = {}) {
  std::vector<float> spatial;  // the CPU's weights, computed the CPU's way
  for (int k = -2; k <= 2; ++k) spatial.push_back(std::exp(-float(k * k) / (2 * 1.5f * 1.5f)));
  std::ostringstream s;
  s << glsl_preamble("NNAO's bilateral blur, one direction per draw")
    << "// Draw the pair uStep = (1, 0), (0, 1) NNAO_BLUR_PAIRS times, each pair on the previous pair's result.\n"
    << "#define NNAO_BLUR_PAIRS " << pairs << "\n"
    << "uniform sampler2D uAO;  // the NNAO pass's output (or the first blur draw's), R32F or R16F\n"
    << "uniform ivec2 uStep;    // (1, 0), then (0, 1) on the first draw's result (image pixels, row 0 at the top)\n"
    << "#define NNAO_BLUR_NORMAL_POWER " << e.normal_power << "\n"
    << "const float BLUR_DEPTH = " << glsl_float(e.depth) << ";  // the depth term's scale, in AO radii\n"
    << glsl_array("SPATIAL", spatial);
  s << R"GLSL(
void main() {
  ivec2 p;
  float z;
  if (!surfacePixel(p, z)) return;
  vec3 n = normalAt(p);
  float invDz = 1.0 / (BLUR_DEPTH * uRadius);
  float s = 0.0, ws = 0.0;
  for (int k = -2; k <= 2; ++k) {
    ivec2 q = p + k * uStep;
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, gSize))) continue;
    float zq = depthAt(q);
    if (isSky(zq)) continue;
    float dz = (zq - z) * invDz;
    vec3 nq = normalAt(q);
    float b = max(0.0, n.x * nq.x + n.y * nq.y + n.z * nq.z), nd = 1.0;
    for (int p = NNAO_BLUR_NORMAL_POWER; p > 0; p >>= 1) {
      if ((p & 1) != 0) nd *= b;
      if (p > 1) b *= b;
    }
    float w = SPATIAL[k + 2] * exp(-(dz * dz)) * nd;
    s += w * texelFetch(uAO, texel(q), 0).r;
    ws += w;
  }
  fragColor = vec4(ws > 0.0 ? s / ws : texelFetch(uAO, texel(p), 0).r);
}
)GLSL";
  return s.str();
}

}  // namespace nns::runs
