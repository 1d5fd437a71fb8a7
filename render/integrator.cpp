#include "render/integrator.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "render/sampling.h"

namespace nns::render {

namespace {
// Packet k of P = ceil(spp / 16) of the shifted Hammersley set of `spp` cosine-weighted
// directions around frame.n; returns how many directions (at most 16) were written.
// wedge = false: the consecutive directions 16k, 16k + 1, ...: one elevation band
// spread over every azimuth. wedge = true: i = k, k + P, k + 2P, ...: i = k mod P fixes
// the low bits of i and so the leading bits of its radical inverse, the azimuth, so
// the packet is a wedge of about 360 / P degrees (22.5 at 256 directions) whose rays
// share more of the BVH (AO alone: 0.67 -> 0.435 CPU-s per nnao view). AO keeps the
// consecutive packets: Embree's answer for a ray grazing an edge can depend on the
// packet it travels in (one AO ray of one pixel in 10 nnao-v2 views changed), and
// the AO datasets must not change.
int cosine_packet(const Frame& frame, int k, int spp, float s1, float s2, bool wedge, Vec3 (&dirs)[16]) {
  const int packets = (spp + 15) / 16;
  const int first = wedge ? k : 16 * k, step = wedge ? packets : 1;
  int count = 0;
  for (int i = first; i < spp && count < 16; i += step) {
    float u1, u2;
    hammersley(uint32_t(i), uint32_t(spp), s1, s2, u1, u2);
    dirs[count++] = frame.to_world(cosine_hemisphere(u1, u2));
  }
  return count;
}
}  // namespace

namespace {
// The random numbers of one pixel's AO: the shift of its Hammersley set.
struct AoShift {
  float s1, s2;
};
AoShift draw_ao_shift(Rng& rng) {
  const float s1 = rng.uniform_float(), s2 = rng.uniform_float();
  return {s1, s2};
}
}  // namespace

float ambient_occlusion(const RayTracer& rt, const Hit& hit, float radius, int spp, Rng& rng) {
  if (spp <= 0) return 1.0f;
  Frame frame(hit.normal);
  Vec3 origin = RayTracer::offset(hit.position, hit.normal);
  const auto [s1, s2] = draw_ao_shift(rng);
  int open = 0;
  Vec3 dirs[16];
  for (int k = 0; k < (spp + 15) / 16; ++k) {
    int count = cosine_packet(frame, k, spp, s1, s2, false, dirs);
    open += count - __builtin_popcount(rt.occluded16(origin, dirs, count, radius));
  }
  return float(open) / float(spp);
}

void skip_ambient_occlusion(int spp, Rng& rng) {
  if (spp > 0) draw_ao_shift(rng);
}

namespace {
// One light's E/pi at p (normal n, ray origin `origin` just above p), `spp` samples of
// an extended light, added to `total`: the terms of direct_light's sum.
void add_sun(const RayTracer& rt, const Sun& sun, Vec3 origin, Vec3 n, int spp, Rng& rng, Accum3& total) {
  Vec3 l = normalize(sun.direction);
  if (sun.angular_radius <= 0) {
    float c = dot(n, l);
    if (c > 0 && !rt.occluded(origin, l, 0.0f, 1e30f)) total.add(sun.color, c);
    return;
  }
  // The disc's colour is its total E/pi at normal incidence; averaging cos * V over
  // the cone gives the penumbra and the small cosine change across the disc.
  Frame f(l);
  float cos_max = std::cos(sun.angular_radius);
  float s1 = rng.uniform_float(), s2 = rng.uniform_float();
  double sum = 0;
  for (int i = 0; i < spp; ++i) {
    float u1, u2;
    hammersley(uint32_t(i), uint32_t(spp), s1, s2, u1, u2);
    Vec3 d = f.to_world(uniform_cone(u1, u2, cos_max));
    float c = dot(n, d);
    if (c > 0 && !rt.occluded(origin, d, 0.0f, 1e30f)) sum += c;
  }
  total.add(sun.color, sum / spp);
}

void add_point(const RayTracer& rt, const PointLight& pl, Vec3 p, Vec3 origin, Vec3 n, Accum3& total) {
  Vec3 to = pl.position - p;  // geometry from the point itself, the ray from above it
  float d2 = dot(to, to);
  float dist = std::sqrt(d2);
  Vec3 l = to / dist;
  float c = dot(n, l);
  if (c > 0 && !rt.occluded(origin, l, 0.0f, dist * (1 - 1e-4f))) total.add(pl.color, c / d2);
}

void add_rect(const RayTracer& rt, const RectLight& rl, Vec3 p, Vec3 origin, Vec3 n, int spp, Rng& rng, Accum3& total) {
  Vec3 nl = cross(rl.edge_u, rl.edge_v);
  float area = length(nl);
  nl = nl / area;
  float s1 = rng.uniform_float(), s2 = rng.uniform_float();
  double sum = 0;
  for (int i = 0; i < spp; ++i) {
    float u1, u2;
    hammersley(uint32_t(i), uint32_t(spp), s1, s2, u1, u2);
    Vec3 to = rl.corner + rl.edge_u * u1 + rl.edge_v * u2 - p;
    float d2 = dot(to, to);
    float dist = std::sqrt(d2);
    Vec3 l = to / dist;
    float c = dot(n, l), cl = -dot(nl, l);
    if (c > 0 && cl > 0 && !rt.occluded(origin, l, 0.0f, dist * (1 - 1e-4f))) sum += c * cl / d2;
  }
  // E/pi = (1/pi) * integral over the rectangle of L cos cos' / r^2 dA.
  total.add(rl.radiance, area * sum / spp / kPi);
}

float luminance(Vec3 c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

// The scene's lights laid out for light_sample's probabilities, built once per pixel:
// per vertex, a weight costs a few multiply-adds (a square root for a point light,
// none for a rect light). A weight is a rough unoccluded E/pi at (p, n); it may be
// anything positive where the light can reach p (the estimate divides by it), but
// must not be 0 where it can: a sun disc counts while any of it is above the
// horizon, a rectangle while p is on its lit side and any corner is above the horizon.
struct LightTable {
  struct SunW {
    Vec3 dir;
    float r, lum;
  };
  struct PointW {
    Vec3 pos;
    float lum;
  };
  struct RectW {
    Vec3 centre, nl;
    float k, lum;
  };  // nl = edge_u x edge_v (area x unit normal), k = nl . corner
  std::vector<SunW> suns;
  std::vector<PointW> points;
  std::vector<RectW> rects;

  explicit LightTable(const Scene& sc) {
    for (const Sun& l : sc.suns)
      suns.push_back({normalize(l.direction), std::max(0.0f, l.angular_radius), luminance(l.color)});
    for (const PointLight& l : sc.points) points.push_back({l.position, luminance(l.color)});
    for (const RectLight& l : sc.rects) {
      Vec3 nl = cross(l.edge_u, l.edge_v);
      rects.push_back({l.corner + l.edge_u * 0.5f + l.edge_v * 0.5f, nl, dot(nl, l.corner), luminance(l.radiance)});
    }
  }
  size_t size() const { return suns.size() + points.size() + rects.size(); }

  // w[0 .. size()): suns, then point lights, then rects (the scene's order); returns the sum.
  float weights(const Scene& sc, Vec3 p, Vec3 n, float* w) const {
    float sum = 0;
    size_t i = 0;
    for (const SunW& l : suns) {
      // Some of the disc is above the horizon iff cos(theta) > -sin(r); r >= sin(r),
      // so c + r > 0 never misses it.
      float c = dot(n, l.dir) + l.r;
      sum += w[i++] = c > 0 ? l.lum * std::min(c, 1.0f) : 0.0f;
    }
    for (const PointW& l : points) {
      Vec3 to = l.pos - p;
      float d2 = dot(to, to), h = dot(n, to);
      float v = h > 0 ? l.lum * h / (d2 * std::sqrt(d2)) : 0.0f;  // cos / d^2
      sum += w[i++] = std::isfinite(v) ? v : 0.0f;                // a lamp at p itself: no direction to it
    }
    for (size_t r = 0; r < rects.size(); ++r) {
      const RectW& l = rects[r];
      float side = dot(l.nl, p) - l.k;  // > 0: p sees the emitting face (x area)
      Vec3 to = l.centre - p;
      float d2 = dot(to, to), h = dot(n, to);
      float v = 0;
      if (side > 0) {
        if (!(h > 0)) h = corner_height(sc.rects[r], p, n) * std::sqrt(d2);
        // Point-source estimate L A cos cos' / (pi d^2) from the centre, with
        // cos = h / d and A cos' = side / d, bounded by the full-hemisphere value L.
        if (h > 0) v = l.lum * std::min(h * side / (kPi * d2 * d2), 1.0f);
      }
      sum += w[i++] = std::isfinite(v) ? v : 0.0f;
    }
    return sum;
  }

  // The centre of a rect is below p's horizon: the largest cosine towards a corner
  // (0 if none is above; the rect is lit only through them then). Rare.
  static float corner_height(const RectLight& l, Vec3 p, Vec3 n) {
    float c = 0;
    const Vec3 q[4] = {l.corner, l.corner + l.edge_u, l.corner + l.edge_v, l.corner + l.edge_u + l.edge_v};
    for (const Vec3& x : q) {
      Vec3 t = x - p;
      float h = dot(n, t);
      if (h > 0) c = std::max(c, h / length(t));
    }
    return c;
  }
};

// `pick` in [0, 1): the uniform number that picks the light (< 0: drawn from rng).
Vec3 light_sample(const RayTracer& rt, const LightTable& lights, Vec3 p, Vec3 n, Rng& rng, LightVisibility* vis,
                  float pick = -1) {
  const Scene& sc = rt.scene();
  const size_t count = lights.size(), ns = lights.suns.size(), np = lights.points.size();
  if (count == 0) return {};
  float local[32];
  std::vector<float> heap;
  float* w = local;
  if (count > 32) {
    heap.resize(count);
    w = heap.data();
  }
  float sum = lights.weights(sc, p, n, w);
  if (vis) {
    sum = 0;
    for (size_t i = 0; i < count; ++i) sum += w[i] *= (vis->unblocked[i] + 1) / (vis->tried[i] + 2);
  }
  if (!(sum > 0)) return {};
  // Pick light k with probability w[k] / sum (the last light of non-zero weight if
  // rounding runs past the end).
  float target = (pick >= 0 ? pick : rng.uniform_float()) * sum, run = 0;
  size_t k = count;
  for (size_t i = 0; i < count; ++i) {
    if (w[i] <= 0) continue;
    k = i;
    run += w[i];
    if (target < run) break;
  }
  Vec3 origin = RayTracer::offset(p, n);
  Accum3 total;
  if (k < ns) add_sun(rt, sc.suns[k], origin, n, 1, rng, total);
  else if (k < ns + np) add_point(rt, sc.points[k - ns], p, origin, n, total);
  else add_rect(rt, sc.rects[k - ns - np], p, origin, n, 1, rng, total);
  if (vis) {  // the sample is 0 exactly when its shadow ray was blocked (or it faced away)
    vis->tried[k] += 1;
    if (total.r != 0 || total.g != 0 || total.b != 0) vis->unblocked[k] += 1;
  }
  return total.mean(double(w[k]) / double(sum));
}
}  // namespace

Vec3 direct_light(const RayTracer& rt, Vec3 p, Vec3 n, int spp, Rng& rng) {
  const Scene& sc = rt.scene();
  Vec3 origin = RayTracer::offset(p, n);
  Accum3 total;
  for (const Sun& sun : sc.suns) add_sun(rt, sun, origin, n, spp, rng, total);
  for (const PointLight& pl : sc.points) add_point(rt, pl, p, origin, n, total);
  for (const RectLight& rl : sc.rects) add_rect(rt, rl, p, origin, n, spp, rng, total);
  return total.mean(1);
}

Vec3 light_sample(const RayTracer& rt, Vec3 p, Vec3 n, Rng& rng, LightVisibility* vis) {
  return light_sample(rt, LightTable(rt.scene()), p, n, rng, vis);
}

namespace {
// Radiance arriving at `p` (normal n) from one cosine-sampled direction, after `depth`
// reflections already taken: sky if the ray escapes, else the outgoing radiance of
// the surface it meets, which itself gathers one more such sample until `bounces`.
// `prefix`: the caller's weight on the result (the first bounce's albedo), which
// Russian roulette (roulette > 0) takes into account.
Vec3 incoming(const RayTracer& rt, const LightTable& lights, LightVisibility& vis, Vec3 p, Vec3 n, Vec3 dir, int depth,
              int bounces, Vec3 prefix, float roulette, Rng& rng) {
  Vec3 throughput(1, 1, 1), result(0, 0, 0);
  for (;;) {
    if (roulette > 0) {
      // prefix x throughput: what the caller multiplies this path's light by.
      float q = std::min(1.0f, roulette * max_abs(prefix * throughput));
      if (q < 1) {
        if (rng.uniform_float() >= q) return result;
        throughput = throughput / q;
      }
    }
    Vec3 origin = RayTracer::offset(p, n);
    if (depth >= bounces) {
      // Last vertex: only the sky may still reach it (its own env term). No ray where
      // the sky is black in that direction (the closed families' sky is black: their
      // rays to it were all blocked anyway).
      Vec3 sky = rt.scene().sky.radiance(dir);
      if (max_abs(sky) > 0 && !rt.occluded(origin, dir, 0.0f, 1e30f)) result += throughput * sky;
      return result;
    }
    Hit h = rt.intersect(origin, dir);
    if (!h.valid()) return result + throughput * rt.scene().sky.radiance(dir);
    const Material& m = *h.material;
    const Vec3 albedo = surface_albedo(m, h.position, h.normal);
    result += throughput * (m.emission + albedo * light_sample(rt, lights, h.position, h.normal, rng, &vis));
    throughput = throughput * albedo;
    if (max_abs(throughput) <= 0) return result;
    p = h.position;
    n = h.normal;
    dir = Frame(n).to_world(cosine_hemisphere(rng.uniform_float(), rng.uniform_float()));
    ++depth;
  }
}
}  // namespace

void env_and_indirect(const RayTracer& rt, const Hit& hit, int spp, int bounces, Rng& rng, Vec3& env, Vec3& indirect,
                      float roulette) {
  env = indirect = Vec3();
  if (spp <= 0) return;
  Frame frame(hit.normal);
  Vec3 origin = RayTracer::offset(hit.position, hit.normal);
  float s1 = rng.uniform_float(), s2 = rng.uniform_float();
  Accum3 e, ind;
  if (bounces == 0) {  // env alone: shadow rays, 16 at a time
    const Sky& sky = rt.scene().sky;
    if (max_abs(sky.zenith) == 0 && max_abs(sky.horizon) == 0 && max_abs(sky.ground) == 0) return;  // env = 0
    Vec3 dirs[16];
    for (int k = 0; k < (spp + 15) / 16; ++k) {
      int count = cosine_packet(frame, k, spp, s1, s2, true, dirs);
      uint32_t blocked = rt.occluded16(origin, dirs, count, 1e30f);
      for (int i = 0; i < count; ++i)
        if (!(blocked >> i & 1u)) e.add(rt.scene().sky.radiance(dirs[i]));
    }
    env = e.mean(spp);
    return;
  }
  // Shared by the pixel's paths, in path order: deterministic for any thread count.
  const LightTable lights(rt.scene());
  LightVisibility vis(rt.scene());
  // The first bounce's own random numbers, stratified over the pixel's paths ("padded"
  // sampling): path i continues in direction order[i] of a second shifted Hammersley
  // set and picks its light with the number (pick[i] + shift) / spp, order and pick
  // being random permutations. Each path's numbers are still uniform and independent
  // of its first direction, so the estimate stays unbiased; across the paths they
  // cover the square and the interval evenly (about 7% less indirect MSE, measured).
  std::vector<uint32_t> order(static_cast<size_t>(spp)), pick(order.size());
  for (uint32_t j = 0; j < uint32_t(spp); ++j) order[j] = pick[j] = j;
  for (size_t j = size_t(spp) - 1; j > 0; --j) std::swap(order[j], order[rng.below(j + 1)]);
  for (size_t j = size_t(spp) - 1; j > 0; --j) std::swap(pick[j], pick[rng.below(j + 1)]);
  const float c1 = rng.uniform_float(), c2 = rng.uniform_float(), c3 = rng.uniform_float();
  for (int i = 0; i < spp; ++i) {
    float u1, u2;
    hammersley(uint32_t(i), uint32_t(spp), s1, s2, u1, u2);
    Vec3 d = frame.to_world(cosine_hemisphere(u1, u2));
    Hit h = rt.intersect(origin, d);
    if (!h.valid()) {
      e.add(rt.scene().sky.radiance(d));
      continue;
    }
    const Material& m = *h.material;
    float v1, v2;
    hammersley(order[size_t(i)], uint32_t(spp), c1, c2, v1, v2);
    Vec3 next = Frame(h.normal).to_world(cosine_hemisphere(v1, v2));
    float u = std::min((float(pick[size_t(i)]) + c3) / float(spp), 0x1.fffffep-1f);
    Vec3 direct = light_sample(rt, lights, h.position, h.normal, rng, &vis, u);
    const Vec3 albedo = surface_albedo(m, h.position, h.normal);
    Vec3 later = incoming(rt, lights, vis, h.position, h.normal, next, 1, bounces, albedo, roulette, rng);
    ind.add(m.emission + albedo * (direct + later));
  }
  env = e.mean(spp);
  indirect = ind.mean(spp);
}

}  // namespace nns::render
