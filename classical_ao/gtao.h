#pragma once
// GTAO (Jimenez, Wu, Pesce & Jarabo 2016, "Practical Real-Time Strategies for Accurate
// Indirect Occlusion"). The cosine-weighted visibility written in polar coordinates
// around the view vector V:
//   A = 1/pi * int_0^pi |proj n(phi)| * int_{h1}^{h2} cos(theta - n) |sin theta| dtheta dphi,
// where the outer integral runs over slices (planes holding V and a screen direction
// phi), n is the angle from V of the normal projected into the slice and |proj n| its
// length, and h1 <= h2 are the slice's two horizon angles measured from V. The paper's
// closed form of the inner integral:
//   a(h1, h2, n) = 1/4 (-cos(2 h1 - n) + cos n + 2 h1 sin n)
//                + 1/4 (-cos(2 h2 - n) + cos n + 2 h2 sin n).
// Per pixel: `slices` slices at evenly spaced angles phi around V (rotated per pixel by
// the 4x4 noise tile, so a 4x4 block holds 16 x slices distinct angles in [0, pi)); in
// each slice, `steps` samples on both sides of the pixel along the screen line that is
// the slice plane's image, finding the highest horizon; then a(), weighted by |proj n|;
// AO = mean over slices; then the 4x4 box blur (the paper's spatial denoise over its 4x4
// noise). The angles are uniform around V, as the outer integral needs, not around the
// screen: away from the image centre, evenly spaced screen directions crowd the slices
// (an open plane seen 30 degrees off-axis read 0.95 that way, see test_gtao).
//
// Horizons are tracked as elevations e above the slice's tangent line (h2 = n + pi/2 -
// e2, h1 = n - pi/2 + e1; the same maximum as the paper's angle from V for a sample in
// the slice), with sin e = N.d / (|d| |proj n|), since N.d = proj n . d for d in the
// slice. Samples are snapped to pixel centres, up to half a pixel off the slice plane;
// measured from V, such a sample of an open plane can sit above the slice's tangent line
// and darken it; measured as an elevation it reads exactly 0, as the plane's points should. Starting e at 0 is the
// paper's clamp of the horizons to the normal's hemisphere.
//
// A sample's elevation fades to 0 over the last `falloff` fraction of the radius
// R = radius_scale * r (XeGTAO's falloff, which avoids a visible edge at R); `thickness`
// lengthens the view-depth component of the distance in that falloff (XeGTAO's
// thin-occluder compensation: a thin object in front occludes less than the depth buffer
// suggests). Step s of a side is at 1 + ((s + jitter) / steps)^distribution * R_px
// pixels (denser near the pixel, where occluders matter most under the cosine). The
// defaults are XeGTAO's default preset (Intel, 2021); tune-classical-ao fits them to a
// dataset.
//
// samples = slices x steps x 2 sides: 4 = 1x2, 8 = 2x2, 16 = 2x4, 32 = 4x4, 64 = 4x8.
//
// gtao() marches 16 pixels of a row at once (simd16.h) with the slice directions and
// step offsets from per-row tables and polynomial acos/asin; gtao_reference() is the
// scalar loop it must match (tests compare them). The *_with forms take parameters.
#include <algorithm>
#include <cmath>
#include <vector>

#include "classical_ao/screen_space_names.h"

namespace nns::classical_ao {

struct GtaoParams {
  float radius_scale = 1.457f;  // XeGTAO "radius multiplier"
  float falloff = 0.615f;       // XeGTAO "falloff range", a fraction of R (0: a hard cut at R)
  float distribution = 2.0f;    // XeGTAO "sample distribution power"
  float thickness = 0.0f;       // XeGTAO "thin occluder compensation"
};

inline void gtao_layout(int samples, int& slices, int& steps) {
  slices = samples >= 32 ? 4 : (samples >= 8 ? 2 : 1);
  steps = samples / (2 * slices) < 1 ? 1 : samples / (2 * slices);
}

namespace gtao_detail {

constexpr float kPi = 3.14159265358979f;

// 1 / (falloff * R): the slope of the fade. falloff 0 means a hard cut at R, kept finite
// (1e-6 R is far below a pixel's footprint) so that (R - d) * slope stays a number.
inline float falloff_slope(const GtaoParams& p, float R) { return 1.0f / (std::max(p.falloff, 1e-6f) * R); }

// Offset in pixels, over R_px, of step s (jitter in [0, 1)).
inline float step_fraction(const GtaoParams& p, int s, int steps, float jitter) {
  return std::pow((float(s) + jitter) / float(steps), p.distribution);
}

inline float slice_angle(int k, int slices, float noise_angle) {
  return (float(k) + noise_angle / 6.2831853f) / float(slices) * kPi;
}

}  // namespace gtao_detail

inline void gtao_reference_with(const GBuffer& g, int samples, float* out, const GtaoParams& p) {
  using namespace gtao_detail;
  int slices, steps;
  gtao_layout(samples, slices, steps);
  std::vector<float> raw(size_t(g.pixels()));
  const float R = g.radius * p.radius_scale, slope = falloff_slope(p, R), zscale = 1.0f + p.thickness;
  for_each_surface_pixel(g, raw.data(), [&](int x, int y, int64_t i, const Vec3& P, const Vec3& N) -> float {
    const Vec3 V = normalize_or_facing(-1.0f * P);
    const float R_px = R * 0.5f * float(g.width) / (g.sx * -P.z);
    if (R_px < 1.0f) {  // the radius covers less than a pixel: nothing to march
      return 1;
    }
    const float noise = noise_angle_4x4(x, y);
    const float jitter = hash_unit(pixel_hash(uint32_t(x & 3), uint32_t(y & 3), 13));
    float sum = 0;
    // A frame around V (V.z > 0: the pixel is in front of the camera).
    const Vec3 e1 = normalize_or_facing(Vec3{V.z, 0, -V.x}), e2 = cross(V, e1);
    for (int k = 0; k < slices; ++k) {
      const float phi = slice_angle(k, slices, noise), c = std::cos(phi), s = std::sin(phi);
      // The slice plane is span(V, T), T = cos phi e1 + sin phi e2 (positive angles on
      // the T side), A its normal; its points project to the screen line through the
      // pixel along D, the direction in the plane with D.z = 0.
      const Vec3 T = c * e1 + s * e2;
      const Vec3 A = cross(T, V);
      const Vec3 D = T - (T.z / V.z) * V;
      const float dlen = std::sqrt(D.x * D.x + D.y * D.y);
      const float ox = D.x / dlen, oy = -D.y / dlen;  // screen direction (pixels, y down)
      const Vec3 PN = N - dot(A, N) * A;
      const float plen = length(PN);
      if (!(plen > 0)) continue;  // the normal is the slice's normal: weight 0
      const float cos_n = saturate(dot(PN, V) / plen), inv_plen = 1.0f / plen;
      const float n = (dot(PN, T) < 0 ? -1.0f : 1.0f) * std::acos(cos_n);
      float sin_e[2] = {0, 0};  // + side (along D), - side
      for (int side = 0; side < 2; ++side) {
        const float sg = side == 0 ? 1.0f : -1.0f;
        for (int st = 0; st < steps; ++st) {
          const float t = 1.0f + step_fraction(p, st, steps, jitter) * R_px;
          const float qx = float(x) + sg * ox * t, qy = float(y) + sg * oy * t;
          if (!g.on_screen(qx, qy)) break;
          int jx, jy;
          g.clamped_pixel(qx, qy, jx, jy);
          const int64_t j = int64_t(jy) * g.width + jx;
          if (g.sky(j)) continue;
          const Vec3 d = g.position(jx, jy) - P;
          const float d2 = dot(d, d);
          if (!(d2 > 0)) continue;
          const float dz = d.z * zscale;
          const float w = saturate((R - std::sqrt(d.x * d.x + d.y * d.y + dz * dz)) * slope);
          sin_e[side] = std::max(sin_e[side], w * (dot(N, d) / std::sqrt(d2) * inv_plen));
        }
      }
      const float h2 = n + 0.5f * kPi - std::asin(std::min(1.0f, sin_e[0]));
      const float h1 = n - 0.5f * kPi + std::asin(std::min(1.0f, sin_e[1]));
      const float sin_n = std::sin(n);
      const float a = 0.25f * (-std::cos(2 * h1 - n) + cos_n + 2 * h1 * sin_n) +
                      0.25f * (-std::cos(2 * h2 - n) + cos_n + 2 * h2 * sin_n);
      sum += plen * a;
    }
    // No clamp here: with few slices a pixel's mean over-estimates or under-estimates
    // the outer integral (it is 1 only on average over phi on an open surface); the
    // blur averages 16 rotations first.
    return sum / float(slices);
  });
  box_blur_4x4_reference(g, raw.data(), out);
  for (int64_t i = 0; i < g.pixels(); ++i) out[i] = std::min(out[i], 1.0f);
}

inline void gtao_reference(const GBuffer& g, int samples, float* out) {
  gtao_reference_with(g, samples, out, GtaoParams{});
}

// acos and asin on 16 lanes, beside the screen-space kit's vector operations.
namespace simd {

using namespace screen_space::simd;

// acos on [-1, 1] from Cephes' asinf polynomial (|error| < 1e-6 rad, tested against
// std::acos): acos x = pi/2 - asin x for |x| <= 1/2, else 2 asin(sqrt((1 - |x|) / 2)),
// reflected to pi - that for x < 0.
inline VF acos(VF x) {
  const VF a = abs(x), half = splat(0.5f);
  const Mask big = gt(a, half);
  const VF z = select(big, half * (splat(1.0f) - a), x * x);
  const VF s = select(big, sqrt(z), a);
  VF poly = splat(4.2163199048e-2f);
  poly = poly * z + splat(2.4181311049e-2f);
  poly = poly * z + splat(4.5470025998e-2f);
  poly = poly * z + splat(7.4953002686e-2f);
  poly = poly * z + splat(1.6666752422e-1f);
  const VF as = s + s * z * poly;  // asin(s), s >= 0
  const Mask neg = lt(x, splat(0.0f));
  const VF big_res = select(neg, splat(gtao_detail::kPi) - (as + as), as + as);
  const VF small_res = splat(0.5f * gtao_detail::kPi) - select(neg, -as, as);
  return select(big, big_res, small_res);
}

// asin on [0, 1] (elevations are never negative): pi/2 - acos.
inline VF asin(VF x) { return splat(0.5f * gtao_detail::kPi) - acos(x); }

}  // namespace simd

inline void gtao_with(const GBuffer& g, int samples, float* out, const GtaoParams& p) {
  using namespace screen_space::simd;
  using namespace simd;
  using namespace gtao_detail;
  int slices, steps;
  gtao_layout(samples, slices, steps);
  std::vector<float> raw(size_t(g.pixels()));
  const float R = g.radius * p.radius_scale, slope = falloff_slope(p, R), zscale = 1.0f + p.thickness;
  const NoiseTile noise;
  // Per row class yq = y & 3 and lane: each slice's screen direction and each step's
  // offset fraction (with the pixel's jitter), the values the reference computes.
  std::vector<float> ocos(size_t(4 * slices * kLanes)), osin(ocos.size()), frac(size_t(4 * steps * kLanes));
  for (int yq = 0; yq < 4; ++yq)
    for (int l = 0; l < kLanes; ++l) {
      const float jitter = hash_unit(pixel_hash(uint32_t(l & 3), uint32_t(yq), 13));
      for (int s = 0; s < steps; ++s) frac[size_t((yq * steps + s) * kLanes + l)] = step_fraction(p, s, steps, jitter);
      for (int k = 0; k < slices; ++k) {
        const float phi = slice_angle(k, slices, noise.angle[yq][l]);
        ocos[size_t((yq * slices + k) * kLanes + l)] = std::cos(phi);
        osin[size_t((yq * slices + k) * kLanes + l)] = std::sin(phi);
      }
    }
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const Block b(g, x0, y, valid);
    const VF zero = splat(0.0f), one = splat(1.0f), quarter = splat(0.25f), two = splat(2.0f);
    const VF R_px = splat(R * 0.5f * float(g.width)) / (splat(g.sx) * b.z);
    const Mask live = b.live & ~lt(R_px, one);
    VF sum = zero;
    if (live) {
      VF nx, ny, nz;
      load_unit_normals(g, b.i0, valid, nx, ny, nz);
      VF vx = zero - b.px, vy = zero - b.py, vz = b.z;  // -P (P = (px, py, -z))
      normalize_or_facing(vx, vy, vz);
      VF e1x = vz, e1y = zero, e1z = zero - vx;
      normalize_or_facing(e1x, e1y, e1z);
      const VF e2x = vy * e1z - vz * e1y, e2y = vz * e1x - vx * e1z, e2z = vx * e1y - vy * e1x;
      const VF inv_vz = one / vz;
      for (int k = 0; k < slices; ++k) {
        const VF c = load(ocos.data() + size_t(((y & 3) * slices + k) * kLanes));
        const VF sn = load(osin.data() + size_t(((y & 3) * slices + k) * kLanes));
        const VF tx = c * e1x + sn * e2x, ty = c * e1y + sn * e2y, tz = c * e1z + sn * e2z;
        const VF ax = ty * vz - tz * vy, ay = tz * vx - tx * vz, az = tx * vy - ty * vx;
        const VF tv = tz * inv_vz;
        const VF Dx = tx - tv * vx, Dy = ty - tv * vy;
        const VF inv_dlen = one / sqrt(Dx * Dx + Dy * Dy);
        const VF ox = Dx * inv_dlen, oy = (zero - Dy) * inv_dlen;
        const VF an = ax * nx + ay * ny + az * nz;
        const VF pnx = nx - an * ax, pny = ny - an * ay, pnz = nz - an * az;
        const VF plen = sqrt(pnx * pnx + pny * pny + pnz * pnz);
        const Mask has_n = live & gt(plen, zero);
        const VF cos_n = saturate(select(has_n, (pnx * vx + pny * vy + pnz * vz) / plen, one));
        const VF inv_plen = select(has_n, one / plen, zero);
        const Mask neg_n = lt(pnx * tx + pny * ty + pnz * tz, zero);
        const VF abs_n = acos(cos_n), abs_sin = sqrt(max(zero, one - cos_n * cos_n));
        const VF n = select(neg_n, -abs_n, abs_n), sin_n = select(neg_n, -abs_sin, abs_sin);
        VF sin_e[2] = {zero, zero};
        for (int side = 0; side < 2; ++side) {
          const VF sx = splat(side == 0 ? 1.0f : -1.0f) * ox, sy = splat(side == 0 ? 1.0f : -1.0f) * oy;
          Mask alive = has_n;
          for (int s = 0; s < steps && alive; ++s) {
            const VF t = one + load(frac.data() + size_t(((y & 3) * steps + s) * kLanes)) * R_px;
            const VF qx = b.X + sx * t, qy = b.Y + sy * t;
            VF dx, dy, dz;
            Mask m = b.sample(g, qx, qy, alive, dx, dy, dz);
            const VF d2 = dx * dx + dy * dy + dz * dz;
            m &= gt(d2, zero);
            const VF dzs = dz * splat(zscale);
            const VF w = saturate((splat(R) - sqrt(dx * dx + dy * dy + dzs * dzs)) * splat(slope));
            const VF e = w * ((nx * dx + ny * dy + nz * dz) / sqrt(d2) * inv_plen);
            sin_e[side] = select(m, max(sin_e[side], e), sin_e[side]);
          }
        }
        // a() with h2 = n + pi/2 - e2 and h1 = n - pi/2 + e1, where -cos(2 h2 - n) =
        // cos(n - 2 e2) and -cos(2 h1 - n) = cos(n + 2 e1), expanded with cos 2e = 1 - 2 s^2
        // and sin 2e = 2 s sqrt(1 - s^2) for s = sin e: no trigonometry beyond three inverses.
        const VF s2 = min(one, sin_e[0]), s1 = min(one, sin_e[1]);
        const VF c2 = sqrt(one - s2 * s2), c1 = sqrt(one - s1 * s1);
        const VF e2 = asin(s2), e1 = asin(s1);
        const VF half_pi = splat(0.5f * kPi);
        const VF h2 = n + half_pi - e2, h1 = n - half_pi + e1;
        const VF cos_a2 = cos_n * (one - two * s2 * s2) + sin_n * (two * s2 * c2);  // cos(n - 2 e2)
        const VF cos_a1 = cos_n * (one - two * s1 * s1) - sin_n * (two * s1 * c1);  // cos(n + 2 e1)
        const VF a = quarter * (cos_a1 + cos_n + two * h1 * sin_n) + quarter * (cos_a2 + cos_n + two * h2 * sin_n);
        sum = sum + select(has_n, plen * a, zero);
      }
    }
    const VF res = sum / splat(float(slices));
    store(raw.data() + b.i0, select(live, res, one), valid);
  });
  box_blur_4x4(g, raw.data(), out);
  for (int64_t i = 0; i < g.pixels(); ++i) out[i] = std::min(out[i], 1.0f);
}

inline void gtao(const GBuffer& g, int samples, float* out) { gtao_with(g, samples, out, GtaoParams{}); }

}  // namespace nns::classical_ao
