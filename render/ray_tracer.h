#pragma once
// RayTracer: an Embree 3 BVH over a Scene's triangles; closest-hit and any-hit queries.
// Thread-safe after construction (Embree's rtcIntersect1/rtcOccluded1 are).
#include <cstdint>

#include "render/scene.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace nns::render {

struct Hit {
  float t = 0;  // distance along the (unit) ray direction
  Vec3 position;
  Vec3 normal;  // unit shading normal: geometric, or interpolated (Scene::normals)
                // and turned to the side of the geometric normal that faces the ray
  uint32_t triangle = 0;
  const Material* material = nullptr;
  bool valid() const { return material != nullptr; }
};

class RayTracer {
 public:
  explicit RayTracer(const Scene& scene);
  ~RayTracer();
  RayTracer(const RayTracer&) = delete;
  RayTracer& operator=(const RayTracer&) = delete;

  // Closest hit in (tnear, tfar); invalid Hit on a miss. `dir` must be unit length.
  Hit intersect(Vec3 origin, Vec3 dir, float tnear = 0, float tfar = 1e30f) const;
  // True if anything lies in (tnear, tfar) along the ray.
  bool occluded(Vec3 origin, Vec3 dir, float tnear, float tfar) const;
  // Up to 16 rays from one origin at once (Embree's packet traversal: rays leaving
  // one point share most BVH nodes). Bit i of the result = ray i is occluded.
  uint32_t occluded16(Vec3 origin, const Vec3* dirs, int count, float tfar) const;

  // A ray origin just above a surface point, so secondary rays do not re-hit it.
  // The offset scales with the coordinate magnitude (float spacing grows with it).
  static Vec3 offset(Vec3 p, Vec3 n) { return p + n * (1e-4f * (1.0f + max_abs(p))); }

  const Scene& scene() const { return scene_; }
  // Rays traced so far by the calling thread (any RayTracer), for throughput figures:
  // a per-thread count costs nothing per ray, a shared atomic would.
  static uint64_t thread_ray_count();

 private:
  const Scene& scene_;
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* rtc_scene_ = nullptr;
};

}  // namespace nns::render
