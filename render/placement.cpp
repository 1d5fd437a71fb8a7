#include "render/placement.h"

#include <algorithm>
#include <cmath>

namespace nns::render {

ProbeResult probe_view(const RayTracer& rt, const Camera& cam) {
  Camera probe = cam;
  probe.height = 14;
  probe.width = std::max(4, int(std::lround(14.0 * cam.width / cam.height)));
  std::vector<Vec3> pos, nrm;
  std::vector<float> depth;
  int sky = 0, total = probe.width * probe.height;
  float nearest = 1e30f;
  for (int y = 0; y < probe.height; ++y)
    for (int x = 0; x < probe.width; ++x) {
      float dpt;
      Vec3 d = probe.pixel_ray(x, y, dpt);
      Hit h = rt.intersect(probe.eye, d);
      if (!h.valid()) {
        ++sky;
        continue;
      }
      pos.push_back(h.position);
      nrm.push_back(h.normal);
      depth.push_back(h.t * dpt);
      nearest = std::min(nearest, h.t);
    }
  // Rays in the six axis directions catch a wall just beside or behind the eye.
  for (Vec3 d : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)}) {
    Hit h = rt.intersect(cam.eye, d);
    if (h.valid()) nearest = std::min(nearest, h.t);
  }
  ProbeResult r;
  r.sky_fraction = float(sky) / float(total);
  r.nearest = nearest;
  if (depth.empty()) return r;
  std::nth_element(depth.begin(), depth.begin() + depth.size() / 2, depth.end());
  r.median_depth = depth[depth.size() / 2];
  // Largest set of hits on one plane: O(n^2) on a few hundred probe rays.
  size_t best = 0;
  for (size_t i = 0; i < pos.size(); ++i) {
    size_t same = 0;
    float di = dot(nrm[i], pos[i]);
    for (size_t j = 0; j < pos.size(); ++j)
      if (dot(nrm[i], nrm[j]) > 0.9994f && std::fabs(dot(nrm[i], pos[j]) - di) < 0.03f) ++same;
    best = std::max(best, same);
  }
  r.plane_fraction = float(best) / float(pos.size());
  return r;
}

namespace {
int violations(const ProbeResult& p, const PlacementRules& rules) {
  return int(p.sky_fraction > rules.max_sky_fraction) + int(p.plane_fraction > rules.max_plane_fraction) +
         int(p.median_depth < rules.min_median_depth) + int(p.nearest < rules.min_clearance);
}

Camera random_camera(const CameraRegion& reg, int width, int height, float fov, Rng& rng) {
  Vec3 eye(float(rng.uniform(reg.min.x, reg.max.x)), float(rng.uniform(reg.min.y, reg.max.y)),
           float(rng.uniform(reg.min.z, reg.max.z)));
  float yaw = (reg.yaw_center_deg + float(rng.uniform(-0.5, 0.5)) * reg.yaw_range_deg) * kPi / 180;
  float pitch = float(rng.uniform(reg.pitch_min_deg, reg.pitch_max_deg)) * kPi / 180;
  Camera c = Camera::from_yaw_pitch(eye, yaw, pitch);
  c.width = width, c.height = height, c.fov_y_deg = fov;
  return c;
}
}  // namespace

bool acceptable(const ProbeResult& p, const PlacementRules& rules) { return violations(p, rules) == 0; }

Camera place_camera(const RayTracer& rt, int width, int height, float fov, Rng& rng, const PlacementRules& rules) {
  const CameraRegion& reg = rt.scene().cameras;
  Camera best, best_ok;
  int best_v = 1 << 30, found = 0;
  float best_sky = 2, best_plane = 2;
  for (int t = 0; t < rules.max_tries && found < rules.candidates; ++t) {
    Camera c = random_camera(reg, width, height, fov, rng);
    ProbeResult p = probe_view(rt, c);
    int v = violations(p, rules);
    if (v == 0) {
      ++found;
      if (p.plane_fraction < best_plane) best_ok = c, best_plane = p.plane_fraction;
    }
    if (v < best_v || (v == best_v && p.sky_fraction < best_sky)) best = c, best_v = v, best_sky = p.sky_fraction;
  }
  return found ? best_ok : best;
}

std::vector<Camera> camera_path(const RayTracer& rt, int width, int height, float fov, int frames, Rng& rng,
                                const PlacementRules& rules) {
  Camera start = place_camera(rt, width, height, fov, rng, rules);
  // Recover the start's yaw and pitch from its forward vector.
  Vec3 f = start.forward();
  float yaw0 = std::atan2(-f.x, -f.z), pitch0 = std::asin(std::clamp(f.y, -1.0f, 1.0f));
  for (int attempt = 0; attempt < 40; ++attempt) {
    float heading = yaw0 + float(rng.uniform(-1.2, 1.2));
    float speed = float(rng.uniform(0.025, 0.05));
    float yaw_rate = float(rng.uniform(-0.012, 0.012)), sway = float(rng.uniform(0, 0.3));
    Vec3 dir(-std::sin(heading), 0, -std::cos(heading)), side(dir.z, 0, -dir.x);
    std::vector<Camera> path;
    Vec3 prev = start.eye;
    bool ok = true;
    for (int i = 0; i < frames && ok; ++i) {
      float t = float(i);
      Vec3 eye = start.eye + dir * (speed * t) + side * (sway * std::sin(t * 0.15f)) * 0.1f +
                 Vec3(0, 0.05f * std::sin(t * 0.1f), 0);
      Camera c = Camera::from_yaw_pitch(eye, yaw0 + yaw_rate * t, pitch0 + 0.05f * std::sin(t * 0.07f));
      c.width = width, c.height = height, c.fov_y_deg = fov;
      // The step must be free of geometry, with clearance around the new eye.
      Vec3 step = eye - prev;
      float len = length(step);
      if (len > 0 && rt.occluded(prev, step / len, 0.0f, len + rules.min_clearance)) ok = false;
      if (probe_view(rt, c).nearest < rules.min_clearance) ok = false;
      prev = eye;
      path.push_back(c);
    }
    if (ok) return path;
  }
  std::vector<Camera> pan;  // a slow pan in place cannot collide
  for (int i = 0; i < frames; ++i) {
    Camera c = Camera::from_yaw_pitch(start.eye, yaw0 + 0.01f * float(i), pitch0);
    c.width = width, c.height = height, c.fov_y_deg = fov;
    pan.push_back(c);
  }
  return pan;
}

}  // namespace nns::render
