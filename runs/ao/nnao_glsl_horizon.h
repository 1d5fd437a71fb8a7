#pragma once
// The horizon model's NNAO pass as GLSL (models/nnao/horizon_simd.h, the exact
// inference nnao-infer runs before its blur): per pixel, D screen directions (the
// first along the normal's screen projection) marched S steps out to the AO radius,
// the running maximum elevation at the end of each band, N.V, the radius in pixels and
// the bands' visibilities, each added into layer 0 as soon as it is known; then the
// head, plus the last band's visibility (the model predicts the residual). The march
// is the model's: D x S depth fetches, trained as such, so the sample count is not a
// uniform; nor is there a frame uniform (the model has no jitter to vary: its
// temporal stability is the blur's, docs/nnao.md).
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "runs/ao/nnao_glsl.h"

namespace nns::runs {

inline std::string glsl_horizon_pass(const nnao::NnaoWeights& m) {
  const nnao::HorizonLayout& L = m.input.horizon;
  // The directions' rotations and the steps' squared fractions, computed in float as
  // the CPU computes them, so the shader marches through the same points.
  std::vector<float> cos_a, sin_a, f2;
  for (int k = 0; k < L.directions; ++k) {
    const float a = 6.2831853f * float(k) / float(L.directions);
    cos_a.push_back(std::cos(a)), sin_a.push_back(std::sin(a));
  }
  for (int s = 0; s < L.steps; ++s) {
    const float f = (float(s) + 0.5f) / float(L.steps);
    f2.push_back(f * f);
  }
  std::ostringstream s;
  s << glsl_preamble("NNAO pass of a horizon model (" + std::to_string(L.directions) + " directions x " +
                     std::to_string(L.steps) + " steps, " + std::to_string(L.bands) + " bands)")
    << "const int DIRS = " << L.directions << ", STEPS = " << L.steps << ", BANDS = " << L.bands
    << ", F = " << m.features() << ";\n"
    << "const float RADIUS_TERM_MAX = " << glsl_float(std::isfinite(L.radius_term_max) ? L.radius_term_max : 3.0e38f)
    << ";  // the radius term's ceiling (none: 3e38)\n"
    << glsl_array("COS_A", cos_a) << glsl_array("SIN_A", sin_a) << glsl_array("STEP_F2", f2)
    << "// Layer 0 (standardisation folded in): weight of feature q in hidden unit k is W0[k * F + q].\n"
    << glsl_array("W0", m.w0) << glsl_head(m);
  s << R"GLSL(
float h[H];  // layer 0's sums
void addFeature(int q, float v) { for (int k = 0; k < H; ++k) h[k] += W0[k * F + q] * v; }

void main() {
  ivec2 p;
  float z;
  if (!surfacePixel(p, z)) return;
  vec3 n = normalAt(p);
  float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  vec3 N = len > 0.0 ? vec3((1.0 / len) * n.x, (1.0 / len) * n.y, (1.0 / len) * n.z) : vec3(0.0, 0.0, 1.0);
  vec2 P = viewXY(vec2(p), z);
  float r = uRadius, r2 = r * r;
  float radiusPx = (r * 0.5 * float(gSize.x)) / (uTanHalfFov.x * z);
  // The first direction: the normal's screen projection (y down); facing the camera, +x.
  float sxn = N.x, syn = 0.0 - N.y, sl = sqrt(sxn * sxn + syn * syn);
  float c0 = sl > 1e-4 ? sxn / sl : 1.0, s0 = sl > 1e-4 ? syn / sl : 0.0;
  float occluded[BANDS];
  for (int b = 0; b < BANDS; ++b) occluded[b] = 0.0;
  for (int k = 0; k < H; ++k) h[k] = 0.0;
  for (int d = 0; d < DIRS; ++d) {
    float ox = c0 * COS_A[d] - s0 * SIN_A[d], oy = s0 * COS_A[d] + c0 * SIN_A[d];
    float horizon = 0.0;
    bool alive = true;  // the march stops at the screen's edge
    for (int st = 0; st < STEPS; ++st) {
      if (alive) {
        float t = 1.0 + STEP_F2[st] * radiusPx;
        float qx = float(p.x) + ox * t, qy = float(p.y) + oy * t;
        alive = qx > -0.5 && qy > -0.5 && qx < float(gSize.x) - 0.5 && qy < float(gSize.y) - 0.5;
        if (alive) {
          ivec2 q = clamp(ivec2(floor(vec2(qx, qy) + 0.5)), ivec2(0), gSize - 1);
          float zq = depthAt(q);
          if (!isSky(zq)) {
            vec2 v = viewXY(vec2(q), zq) - P;
            float vz = z - zq;
            float d2 = v.x * v.x + v.y * v.y + vz * vz;
            // Beyond r the ground truth's rays do not reach: no occluder.
            if (d2 > 0.0 && d2 <= r2) horizon = max(horizon, (N.x * v.x + N.y * v.y + N.z * vz) / sqrt(d2));
          }
        }
      }
      if ((st + 1) % (STEPS / BANDS) == 0) {
        int band = (st + 1) / (STEPS / BANDS) - 1;
        addFeature(d * BANDS + band, horizon);
        occluded[band] += horizon * horizon;
      }
    }
  }
  vec3 V = vec3(0.0 - P.x, 0.0 - P.y, z);  // towards the camera
  float lv = sqrt(V.x * V.x + V.y * V.y + V.z * V.z);
  addFeature(DIRS * BANDS, N.x * ((1.0 / lv) * V.x) + N.y * ((1.0 / lv) * V.y) + N.z * ((1.0 / lv) * V.z));
  addFeature(DIRS * BANDS + 1, min(RADIUS_TERM_MAX, log2(1.0 + radiusPx) / 8.0));
  float base = 1.0;
  for (int b = 0; b < BANDS; ++b) {
    base = 1.0 - occluded[b] / float(DIRS);  // an occluder at elevation e hides sin^2 e
    addFeature(DIRS * BANDS + 2 + b, base);
  }
  fragColor = vec4(nnaoHead(h, 1.0, base));
}
)GLSL";
  return s.str();
}

}  // namespace nns::runs
