#include "render/scenes/scene_variation.h"

#include <algorithm>
#include <cmath>

#include "render/sampling.h"

namespace nns::render {

namespace {

float log_uniform(Rng& rng, float lo, float hi) {
  return float(std::exp(rng.uniform(std::log(double(lo)), std::log(double(hi)))));
}

Vec3 hsv(float h, float s, float v) {
  auto f = [&](float n) {
    float k = std::fmod(n + h * 6, 6.0f);
    return v - v * s * std::max(0.0f, std::min({k, 4 - k, 1.0f}));
  };
  return {f(5), f(3), f(1)};
}

Vec3 draw_albedo(Rng& rng, const LightingVariation& v) {
  if (rng.uniform() < v.colour_share) {
    float h = float(rng.uniform()), s = float(rng.uniform(v.saturation_min, v.saturation_max));
    return hsv(h, s, float(rng.uniform(v.grey_min + 0.1, v.grey_max)));
  }
  float g = float(rng.uniform(v.grey_min, v.grey_max));
  Vec3 tint(float(rng.uniform(0.92, 1.08)), float(rng.uniform(0.92, 1.08)), float(rng.uniform(0.92, 1.08)));
  return vmin(tint * g, Vec3(0.9f));
}

// A light colour between warm (tungsten, ~2700 K) and cool (overcast, ~7000 K), as an
// RGB multiplier with luminance about 1.
Vec3 draw_light_tint(Rng& rng) {
  float t = float(rng.uniform(-1, 1));  // -1 warm .. +1 cool
  Vec3 warm(1.25f, 0.95f, 0.62f), cool(0.85f, 0.97f, 1.25f), white(1, 1, 1);
  return t < 0 ? lerp(white, warm, -t) : lerp(white, cool, t);
}

}  // namespace

void vary_materials_and_lights(Scene& s, Rng& rng, const LightingVariation& v) {
  // Emissive materials (lamp panels, glowing parts) keep their albedo: they stand for
  // the lights whose exposure is scaled below.
  const float exposure = log_uniform(rng, v.exposure_min, v.exposure_max);
  for (Material& m : s.materials) {
    if (m.emission.x > 0 || m.emission.y > 0 || m.emission.z > 0) {
      m.emission = m.emission * exposure;
      continue;
    }
    m.albedo = draw_albedo(rng, v);
  }
  for (Sun& sun : s.suns) {
    float az = float(rng.uniform(0, 2 * kPi));
    float el = float(rng.uniform(v.sun_elevation_min, v.sun_elevation_max)) * kPi / 180;
    sun.direction = {std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az)};
    sun.angular_radius = log_uniform(rng, v.sun_radius_min, v.sun_radius_max);
    sun.color = sun.color * draw_light_tint(rng) * exposure;
  }
  for (PointLight& p : s.points) p.color = p.color * draw_light_tint(rng) * exposure;
  for (RectLight& r : s.rects) r.radiance = r.radiance * draw_light_tint(rng) * exposure;
  const float sky_scale = exposure * float(rng.uniform(0.6, 1.4));
  s.sky.zenith = s.sky.zenith * sky_scale, s.sky.horizon = s.sky.horizon * sky_scale;
  s.sky.ground = s.sky.ground * sky_scale;

  if (rng.uniform() < v.lamp_share) {
    Vec3 lo, hi;
    s.bounds(lo, hi);
    const Vec3 grow(v.lamp_region_grow);
    Vec3 a = vmax(s.cameras.min - grow, lo), b = vmin(s.cameras.max + grow, hi);
    a = vmin(a, b);  // a camera region outside the geometry's box: keep the box's corner
    for (int k = 1 + int(rng.below(uint64_t(v.lamps_max))); k > 0; --k) {
      Vec3 pos(float(rng.uniform(a.x, b.x)), float(rng.uniform(a.y, b.y)), float(rng.uniform(a.z, b.z)));
      s.points.push_back({pos, draw_light_tint(rng) * log_uniform(rng, v.lamp_min, v.lamp_max) * exposure});
    }
  }
}

}  // namespace nns::render
