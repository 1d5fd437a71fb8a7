#pragma once
// Shared pieces of the scene generators: palettes, lighting rigs, a wall with holes.
#include <cmath>

#include "core/rng.h"
#include "render/sampling.h"
#include "render/scenes/builder.h"

namespace nns::render {

// A muted random colour: albedo in [lo, hi] per channel, around a random hue.
inline Material random_material(Rng& rng, float lo = 0.2f, float hi = 0.85f) {
  float base = float(rng.uniform(lo, hi));
  Vec3 tint(float(rng.uniform(0.8, 1.15)), float(rng.uniform(0.8, 1.15)), float(rng.uniform(0.8, 1.15)));
  Vec3 a = tint * base;
  return {vmin(a, Vec3(0.9f)), {}};
}

// Outdoor light: a sun at a random azimuth, elevation in [elev_lo, elev_hi] degrees,
// and a blue gradient sky; sun colour scaled so a surface facing it gets ~3x the sky.
inline void outdoor_lighting(Scene& s, Rng& rng, float elev_lo = 20, float elev_hi = 65) {
  float az = float(rng.uniform(0, 2 * kPi));
  float el = float(rng.uniform(elev_lo, elev_hi)) * kPi / 180;
  Vec3 dir(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az));
  float warm = float(rng.uniform(0, 0.25));
  s.suns.push_back({dir, Vec3(3.0f, 3.0f - warm, 3.0f - 2 * warm), 0.0093f});  // the real sun's radius
  s.sky = Sky{{0.25f, 0.45f, 0.9f}, {0.7f, 0.8f, 0.95f}, {0.15f, 0.13f, 0.1f}};
}

// An axis-aligned wall in the plane z = z0 (or x = x0 when along_x is false) from
// a0..a1 along its length, 0..height tall, `thick` thick, with rectangular holes
// (window / door openings) given as {a_lo, a_hi, y_lo, y_hi}.
struct Opening {
  float a0, a1, y0, y1;
};
// The same wall as a band from y0 to y1 (one storey of a facade): holes sorted along
// the wall, not overlapping, inside the band.
inline void add_wall_band(Scene& s, bool along_x, float plane, float a0, float a1, float y0, float y1, float thick,
                          const std::vector<Opening>& holes, uint32_t m) {
  auto box = [&](float u0, float u1, float v0, float v1) {
    if (u1 - u0 < 1e-4f || v1 - v0 < 1e-4f) return;
    if (along_x) add_box(s, {u0, v0, plane - thick / 2}, {u1, v1, plane + thick / 2}, m);
    else add_box(s, {plane - thick / 2, v0, u0}, {plane + thick / 2, v1, u1}, m);
  };
  float u = a0;
  for (const Opening& h : holes) {
    box(u, h.a0, y0, y1);
    box(h.a0, h.a1, y0, h.y0);
    box(h.a0, h.a1, h.y1, y1);
    u = h.a1;
  }
  box(u, a1, y0, y1);
}
inline void add_wall(Scene& s, bool along_x, float plane, float a0, float a1, float height, float thick,
                     const std::vector<Opening>& holes, uint32_t m) {
  add_wall_band(s, along_x, plane, a0, a1, 0, height, thick, holes, m);
}

// A table: top plus four legs, at (x, z) with yaw.
inline void add_table(Scene& s, Vec3 c, float w, float d, float h, float yaw, uint32_t m) {
  add_box_yaw(s, c + Vec3(0, h - 0.025f, 0), {w / 2, 0.025f, d / 2}, yaw, m);
  float cy = std::cos(yaw), sy = std::sin(yaw);
  for (int i = 0; i < 4; ++i) {
    float lx = (i & 1 ? 1 : -1) * (w / 2 - 0.05f), lz = (i & 2 ? 1 : -1) * (d / 2 - 0.05f);
    Vec3 off(cy * lx + sy * lz, 0, -sy * lx + cy * lz);
    add_box_yaw(s, c + off + Vec3(0, (h - 0.05f) / 2, 0), {0.03f, (h - 0.05f) / 2, 0.03f}, yaw, m);
  }
}

}  // namespace nns::render
