#pragma once
// The grid model's NNAO pass as GLSL: shader-style inference (nnao_inference.h,
// infer_shader_style before its blur): the H filter images of nnao_filters.exr sampled
// on a stratified grid at a per-pixel jitter, the sum rescaled, the network's head.
// The sample count and the frame (the jitter pattern's seed, as eval-ao
// --vary-pattern varies it per frame for temporal accumulation) are uniforms, so an
// engine changes them without a new export; the blur is nnao_glsl_blur.h.
#include <sstream>
#include <string>

#include "runs/ao/nnao_glsl.h"

namespace nns::runs {

inline std::string glsl_grid_pass(const nnao::NnaoWeights& m, int default_samples) {
  std::ostringstream s;
  s << glsl_preamble("NNAO pass of a grid model (Holden et al. 2016, shader-style inference)")
    << "uniform sampler2D uFilters;  // nnao_filters.exr as stored (row j = grid row j, not flipped): (H*W) x W\n"
    << "                             // RGBA32F, filter k in columns [k*W, (k+1)*W), RGBA = Nx, Ny, Nz, depth weights\n"
    << "uniform int uSamples = " << default_samples
    << ";  // filter samples per pixel: 64 = 8 x 8 strata, 128 = 16 x 8, ...\n"
    << "uniform uint uFrame = 0u;   // seed of the jitter pattern: the frame index, for temporal accumulation\n"
    << "const int W = " << m.input.window << ";  // the grid: W x W view-space points spanning [-r, r]\n"
    << glsl_head(m);
  s << R"GLSL(
// screen_space::pixel_hash and screen_space::hash_unit: the CPU path's jitter, uFrame its seed.
uint pixelHash(uint x, uint y, uint salt) {
  uint h = x * 0x8da6b343u ^ y * 0xd8163841u ^ salt * 0xcb1ab31fu;
  h ^= h >> 16; h *= 0x7feb352du; h ^= h >> 15; h *= 0x846ca68bu; h ^= h >> 16;
  return h;
}
float hashUnit(uint h) { return float(h >> 8) * (1.0 / 16777216.0); }

void main() {
  ivec2 p;
  float z;
  if (!surfacePixel(p, z)) return;
  vec3 N = normalAt(p);
  vec2 P = viewXY(vec2(p), z);
  float r = uRadius, invR = 1.0 / r;
  // FeatureCentre: the grid's points share the centre's depth, so a point's pixel is
  // the centre's plus its offset times the pixels per unit at that depth.
  float kx = (0.5 * float(gSize.x)) / (uTanHalfFov.x * z), ky = (0.5 * float(gSize.y)) / (uTanHalfFov.y * z);
  float cx = (P.x / (uTanHalfFov.x * z) + 1.0) * (0.5 * float(gSize.x)) - 0.5;
  float cy = (1.0 - P.y / (uTanHalfFov.y * z)) * (0.5 * float(gSize.y)) - 0.5;
  float step = W == 1 ? 0.0 : 2.0 * r / float(W - 1);
  // sample_grid: mx the power of two at or above sqrt(n), both at most W.
  int n = max(uSamples, 1), mx = 1;
  while (mx * mx < n) mx *= 2;
  int my = min(max(n / mx, 1), W);
  mx = min(mx, W);
  uint h1 = pixelHash(uint(p.x), uint(p.y), uFrame);
  vec2 jit = vec2(hashUnit(h1), hashUnit(pixelHash(h1, 1u, uFrame)));
  float h[H];
  for (int k = 0; k < H; ++k) h[k] = 0.0;
  for (int b = 0; b < my; ++b) {
    int j = clamp(int((float(b) + jit.y) * float(W) / float(my)), 0, W - 1);
    float sy = cy + (float(j) * step - r) * ky;  // row 0 of the grid is +r, up
    for (int a = 0; a < mx; ++a) {
      int i = clamp(int((float(a) + jit.x) * float(W) / float(mx)), 0, W - 1);
      float sx = cx + (float(i) * step - r) * kx;
      ivec2 q = clamp(ivec2(floor(vec2(sx, sy) + 0.5)), ivec2(0), gSize - 1);
      float zs = depthAt(q);
      if (isSky(zs)) continue;
      vec2 d = viewXY(vec2(q), zs) - P;
      float dz = z - zs;
      float d2 = (d.x * d.x + d.y * d.y + dz * dz) * (invR * invR);
      if (!(d2 < 1.0)) continue;  // farther than r: the falloff makes every feature 0
      float f = 1.0 - sqrt(d2);
      vec3 ns = normalAt(q);
      vec4 x = vec4(f * (ns.x - N.x), f * (ns.y - N.y), f * (ns.z - N.z), f * (zs - z) * invR);
      for (int k = 0; k < H; ++k) {
        vec4 w = texelFetch(uFilters, ivec2(k * W + i, j), 0);
        h[k] += w.x * x.x + w.y * x.y + w.z * x.z + w.w * x.w;
      }
    }
  }
  fragColor = vec4(nnaoHead(h, float(W * W) / float(mx * my), 0.0));
}
)GLSL";
  return s.str();
}

}  // namespace nns::runs
