#include "render/render_view.h"

#include <atomic>
#include <chrono>
#include <limits>
#include <stdexcept>

#include "core/thread_pool.h"

namespace nns::render {

namespace {
struct Planes {
  float *z, *nx, *ny, *nz, *ao = nullptr;
  float *alb[3] = {}, *dir[3] = {}, *emi[3] = {}, *env[3] = {}, *ind[3] = {};
};

void put(float* const* rgb, size_t i, Vec3 v) {
  if (!rgb[0]) return;
  rgb[0][i] = v.x, rgb[1][i] = v.y, rgb[2][i] = v.z;
}

void rgb_planes(data::View& v, const char* name, float** out) {
  static const char* suffix[3] = {".R", ".G", ".B"};
  for (int c = 0; c < 3; ++c) out[c] = v.add_channel(std::string(name) + suffix[c]).data();
}
}  // namespace

data::View render_view(const RayTracer& rt, const Camera& cam, const RenderSettings& s, uint64_t view_id,
                       const Camera* normal_frame, RenderStats* stats) {
  if (cam.width <= 0 || cam.height <= 0) throw std::invalid_argument("render_view: empty image size");
  if (s.lighting && s.indirect && s.bounces < 1) throw std::invalid_argument("render_view: bounces must be >= 1");
  auto t0 = std::chrono::steady_clock::now();
  const Scene& sc = rt.scene();
  const Camera& nframe = normal_frame ? *normal_frame : cam;

  data::View v;
  v.width = cam.width;
  v.height = cam.height;
  v.fov_y_deg = cam.fov_y_deg;
  v.scene = sc.name;
  v.world_to_camera = cam.world_to_camera();
  Planes p;
  p.z = v.add_channel("Z").data();
  p.nx = v.add_channel("N.X").data();
  p.ny = v.add_channel("N.Y").data();
  p.nz = v.add_channel("N.Z").data();
  rgb_planes(v, "albedo", p.alb);
  const float ao_radius = s.ao_radius > 0 ? s.ao_radius : sc.ao_radius;
  if (s.ao) {
    v.ao_radius = ao_radius;
    p.ao = v.add_channel("AO").data();
  }
  if (s.lighting) {
    rgb_planes(v, "direct", p.dir);
    rgb_planes(v, "emission", p.emi);
    rgb_planes(v, "env", p.env);
    if (s.indirect) rgb_planes(v, "indirect", p.ind);
  }

  const Rng view_rng = Rng(s.seed).fork(view_id);
  std::atomic<int> next_row{0};
  std::atomic<uint64_t> rays{0};
  // Rows are handed out one at a time (sky rows are cheap, floor rows are not); the
  // split may vary between runs, the pixels cannot, since each owns its Rng.
  ThreadPool::global().run([&](int, int) {
    uint64_t rays0 = RayTracer::thread_ray_count();
    for (int y; (y = next_row.fetch_add(1)) < cam.height;) {
      for (int x = 0; x < cam.width; ++x) {
        size_t i = size_t(y) * size_t(cam.width) + size_t(x);
        Rng rng = view_rng.fork(i);
        float depth_per_t;
        Vec3 d = cam.pixel_ray(x, y, depth_per_t);
        Hit h = rt.intersect(cam.eye, d);
        if (!h.valid()) {
          p.z[i] = std::numeric_limits<float>::infinity();
          if (p.ao) p.ao[i] = 1.0f;
          put(p.emi, i, sc.sky.radiance(d));
          continue;
        }
        p.z[i] = h.t * depth_per_t;
        Vec3 n = nframe.to_camera(h.normal);
        p.nx[i] = n.x, p.ny[i] = n.y, p.nz[i] = n.z;
        put(p.alb, i, surface_albedo(*h.material, h.position, h.normal));
        if (p.ao) p.ao[i] = ambient_occlusion(rt, h, ao_radius, s.ao_spp, rng);
        else skip_ambient_occlusion(s.ao_spp, rng);
        if (s.lighting) {
          put(p.dir, i, direct_light(rt, h.position, h.normal, s.light_spp, rng));
          put(p.emi, i, h.material->emission);
          Vec3 env, ind;
          env_and_indirect(rt, h, s.gi_spp, s.indirect ? s.bounces : 0, rng, env, ind, s.roulette);
          put(p.env, i, env);
          put(p.ind, i, ind);
        }
      }
    }
    rays += RayTracer::thread_ray_count() - rays0;
  });
  if (stats) {
    stats->rays += rays.load();
    stats->seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return v;
}

}  // namespace nns::render
