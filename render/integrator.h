#pragma once
// The per-pixel estimators behind the dataset's ground-truth channels. The
// radiometric definitions are in docs/renderer.md; in short, every lighting channel is
// irradiance / pi (the radiance a white Lambertian surface would reflect), so that
// shaded = albedo * (direct + env + indirect) + emission.
#include <vector>

#include "core/rng.h"
#include "render/ray_tracer.h"

namespace nns::render {

struct RenderSettings {
  int ao_spp = 256;      // AO rays per pixel (cosine-weighted, stratified)
  int gi_spp = 128;      // paths per pixel for env + indirect (stratified first bounce)
  int light_spp = 4;     // samples per area light / sun disc at the visible point
  int bounces = 3;       // indirect bounces (>= 2 for the GI target)
  float roulette = 2;    // Russian roulette on indirect paths (env_and_indirect); 0 = off
  bool ao = true;        // write `AO` (false: its rays are not traced, its random numbers still drawn)
  bool lighting = true;  // write direct / emission / env (and indirect, below)
  bool indirect = true;  // with lighting: also path-trace `indirect`, the GI target
  uint64_t seed = 0;
  float ao_radius = 0;  // > 0: AO radius for this view instead of the scene's (nnao-v2 varies it per view)
  // > 0: AO rays and env rays per pixel on the five non-front faces of a surround frame
  // (0: ao_spp, and min(gi_spp, 64) env rays, as surround .. surround-v4). Set by surround-v5 only.
  int side_spp = 0;
};

// Cosine-weighted fraction of the hemisphere around hit.normal whose rays travel
// `radius` without hitting geometry.
float ambient_occlusion(const RayTracer& rt, const Hit& hit, float radius, int spp, Rng& rng);

// Draws from `rng` what ambient_occlusion(..., spp, rng) draws, and traces nothing: a
// render without the AO channel keeps every other channel bit for bit.
void skip_ambient_occlusion(int spp, Rng& rng);

// Direct light from the scene's suns, point and rect lights, with shadow rays:
// sum_i E_i / pi at the point (before albedo). `spp` samples each extended light.
Vec3 direct_light(const RayTracer& rt, Vec3 p, Vec3 n, int spp, Rng& rng);

// What the shadow rays of one pixel's paths have found so far, per light in the
// scene's order (suns, point lights, rects): light_sample scales a light's probability
// by (unblocked + 1) / (tried + 2), so lights that the pixel's paths keep finding
// behind a wall (a lamp in the next room, the sun outside) are picked less often.
// The probabilities depend only on earlier samples, so each estimate stays unbiased.
struct LightVisibility {
  std::vector<float> unblocked, tried;
  explicit LightVisibility(const Scene& sc)
      : unblocked(sc.suns.size() + sc.points.size() + sc.rects.size(), 0.0f), tried(unblocked.size(), 0.0f) {}
};

// Next-event estimation at a path vertex: the same E/pi as direct_light, estimated
// with one shadow ray (one sample of one light), the light picked with probability
// proportional to an estimate of its unoccluded contribution at (p, n) (times the
// visibility learnt so far, with `vis`, which it updates) and the sample divided by
// that probability. Unbiased; cheap where a scene has many lamps and most of them
// are far, dim, behind p or behind a wall.
Vec3 light_sample(const RayTracer& rt, Vec3 p, Vec3 n, Rng& rng, LightVisibility* vis = nullptr);

// env = sky radiance reaching the point unoccluded, cosine-averaged (E_sky / pi);
// indirect = radiance leaving the first surface each cosine-distributed ray meets
// (its emission plus its albedo times all its own light), cosine-averaged, with up to
// `bounces` reflections along each path. Both share the same `spp` directions.
// bounces = 0 computes env alone (shadow rays only) and leaves indirect at 0.
// roulette > 0: Russian roulette beyond the first bounce: before each further ray a
// path goes on with probability q = min(1, roulette x its largest throughput channel)
// and is divided by q if it does (unbiased; dim paths, which carry little, stop
// early). 0 traces every path to `bounces` (the furnace's zero-variance case).
void env_and_indirect(const RayTracer& rt, const Hit& hit, int spp, int bounces, Rng& rng, Vec3& env, Vec3& indirect,
                      float roulette = 0);

}  // namespace nns::render
