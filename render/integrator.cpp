#include "render/integrator.h"

#include <algorithm>
#include <cmath>

#include "render/sampling.h"

namespace nns::data {

namespace {
// Packet k of P = ceil(spp / 16) of the shifted Hammersley set of `spp` cosine-weighted
// directions around frame.n: directions i = k, k + P, k + 2P, ... (at most 16); returns
// how many were written. Strided, not consecutive, for coherence: consecutive points of
// the set share an elevation band and spread over every azimuth, while i = k mod P
// fixes the low bits of i and so the leading bits of its radical inverse, the azimuth:
// each packet is a wedge of about 360 / P degrees (22.5 at 256 directions), whose rays
// share more of the BVH.
int cosine_packet(const Frame& frame, int k, int spp, float s1, float s2, Vec3 (&dirs)[16]) {
  const int packets = (spp + 15) / 16;
  int count = 0;
  for (int i = k; i < spp && count < 16; i += packets) {
    float u1, u2;
    hammersley(uint32_t(i), uint32_t(spp), s1, s2, u1, u2);
    dirs[count++] = frame.to_world(cosine_hemisphere(u1, u2));
  }
  return count;
}
}  // namespace

float ambient_occlusion(const RayTracer& rt, const Hit& hit, float radius, int spp, Rng& rng) {
  if (spp <= 0) return 1.0f;
  Frame frame(hit.normal);
  Vec3 origin = RayTracer::offset(hit.position, hit.normal);
  float s1 = rng.uniform_float(), s2 = rng.uniform_float();
  int open = 0;
  Vec3 dirs[16];
  for (int k = 0; k < (spp + 15) / 16; ++k) {
    int count = cosine_packet(frame, k, spp, s1, s2, dirs);
    open += count - __builtin_popcount(rt.occluded16(origin, dirs, count, radius));
  }
  return float(open) / float(spp);
}

Vec3 direct_light(const RayTracer& rt, Vec3 p, Vec3 n, int spp, Rng& rng) {
  const Scene& sc = rt.scene();
  Vec3 origin = RayTracer::offset(p, n);
  Accum3 total;
  for (const Sun& sun : sc.suns) {
    Vec3 l = normalize(sun.direction);
    if (sun.angular_radius <= 0) {
      float c = dot(n, l);
      if (c > 0 && !rt.occluded(origin, l, 0.0f, 1e30f)) total.add(sun.color, c);
      continue;
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
  for (const PointLight& pl : sc.points) {
    Vec3 to = pl.position - p;  // geometry from the point itself, the ray from above it
    float d2 = dot(to, to);
    float dist = std::sqrt(d2);
    Vec3 l = to / dist;
    float c = dot(n, l);
    if (c > 0 && !rt.occluded(origin, l, 0.0f, dist * (1 - 1e-4f))) total.add(pl.color, c / d2);
  }
  for (const RectLight& rl : sc.rects) {
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
  return total.mean(1);
}

namespace {
// Radiance arriving at `p` (normal n) from one cosine-sampled direction, after `depth`
// reflections already taken: sky if the ray escapes, else the outgoing radiance of
// the surface it meets, which itself gathers one more such sample until `bounces`.
Vec3 incoming(const RayTracer& rt, Vec3 p, Vec3 n, Vec3 dir, int depth, int bounces, Rng& rng) {
  Vec3 throughput(1, 1, 1), result(0, 0, 0);
  for (;;) {
    Vec3 origin = RayTracer::offset(p, n);
    if (depth >= bounces) {
      // Last vertex: only the sky may still reach it (its own env term).
      if (!rt.occluded(origin, dir, 0.0f, 1e30f)) result += throughput * rt.scene().sky.radiance(dir);
      return result;
    }
    Hit h = rt.intersect(origin, dir);
    if (!h.valid()) return result + throughput * rt.scene().sky.radiance(dir);
    const Material& m = *h.material;
    result += throughput * (m.emission + m.albedo * direct_light(rt, h.position, h.normal, 1, rng));
    throughput = throughput * m.albedo;
    if (max_abs(throughput) <= 0) return result;
    p = h.position;
    n = h.normal;
    dir = Frame(n).to_world(cosine_hemisphere(rng.uniform_float(), rng.uniform_float()));
    ++depth;
  }
}
}  // namespace

void env_and_indirect(const RayTracer& rt, const Hit& hit, int spp, int bounces, Rng& rng, Vec3& env,
                      Vec3& indirect) {
  env = indirect = Vec3();
  if (spp <= 0) return;
  Frame frame(hit.normal);
  Vec3 origin = RayTracer::offset(hit.position, hit.normal);
  float s1 = rng.uniform_float(), s2 = rng.uniform_float();
  Accum3 e, ind;
  if (bounces == 0) {  // env alone: shadow rays, 16 at a time
    Vec3 dirs[16];
    for (int k = 0; k < (spp + 15) / 16; ++k) {
      int count = cosine_packet(frame, k, spp, s1, s2, dirs);
      uint32_t blocked = rt.occluded16(origin, dirs, count, 1e30f);
      for (int i = 0; i < count; ++i)
        if (!(blocked >> i & 1u)) e.add(rt.scene().sky.radiance(dirs[i]));
    }
    env = e.mean(spp);
    return;
  }
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
    Vec3 next = Frame(h.normal).to_world(cosine_hemisphere(rng.uniform_float(), rng.uniform_float()));
    ind.add(m.emission + m.albedo * (direct_light(rt, h.position, h.normal, 1, rng) +
                                     incoming(rt, h.position, h.normal, next, 1, bounces, rng)));
  }
  env = e.mean(spp);
  indirect = ind.mean(spp);
}

}  // namespace nns::data
