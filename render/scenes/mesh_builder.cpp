#include "render/scenes/mesh_builder.h"

#include <cmath>
#include <map>
#include <utility>

#include "render/sampling.h"
#include "render/scenes/builder.h"

namespace nns::render {

void smooth_normals(Scene& s, uint32_t first_vertex, size_t first_triangle) {
  pad_normals(s);
  for (uint32_t i = first_vertex; i < s.normals.size(); ++i) s.normals[i] = Vec3();
  for (size_t t = first_triangle; t < s.triangles.size(); ++t) {
    const auto& v = s.triangles[t].v;
    // Not normalised: the cross product's length is twice the area, so big faces
    // weigh more and slivers (e.g. near a pole) barely count.
    Vec3 fn = cross(s.positions[v[1]] - s.positions[v[0]], s.positions[v[2]] - s.positions[v[0]]);
    for (uint32_t i : v)
      if (i >= first_vertex) s.normals[i] += fn;
  }
  for (uint32_t i = first_vertex; i < s.normals.size(); ++i) s.normals[i] = normalize(s.normals[i]);
}

namespace {
void tri(Scene& s, uint32_t a, uint32_t b, uint32_t c, uint32_t m) { s.triangles.push_back({{a, b, c}, m}); }
void quad(Scene& s, uint32_t a, uint32_t b, uint32_t c, uint32_t d, uint32_t m) {
  tri(s, a, b, c, m);
  tri(s, a, c, d, m);
}
}  // namespace

void add_lathe(Scene& s, Vec3 base, Vec3 axis, const std::vector<ProfilePoint>& profile, int segments, uint32_t m,
               bool smooth, bool closed) {
  if (smooth) pad_normals(s);
  const uint32_t v0 = uint32_t(s.positions.size());
  const size_t t0 = s.triangles.size();
  Frame f(normalize(axis));
  std::vector<Vec3> ring(static_cast<size_t>(segments));
  for (int j = 0; j < segments; ++j) {
    float a = 2 * kPi * float(j) / float(segments);
    ring[size_t(j)] = f.t * std::cos(a) + f.b * std::sin(a);
  }
  // First vertex of each profile point's ring (a pole has one vertex).
  std::vector<uint32_t> first(profile.size());
  for (size_t i = 0; i < profile.size(); ++i) {
    first[i] = uint32_t(s.positions.size());
    Vec3 c = base + f.n * profile[i].y;
    if (profile[i].r == 0) s.positions.push_back(c);
    else
      for (int j = 0; j < segments; ++j) s.positions.push_back(c + ring[size_t(j)] * profile[i].r);
  }
  size_t n = profile.size();
  for (size_t i = 0; i + 1 < n + (closed ? 1 : 0); ++i) {
    size_t k = (i + 1) % n;
    const ProfilePoint &p = profile[i], &q = profile[k];
    if (p.r == q.r && p.y == q.y) continue;  // a repeat: the crease between two rings
    for (int j = 0; j < segments; ++j) {
      uint32_t j1 = uint32_t((j + 1) % segments), jj = uint32_t(j);
      if (p.r == 0 && q.r == 0) break;
      if (p.r == 0) tri(s, first[i], first[k] + j1, first[k] + jj, m);
      else if (q.r == 0) tri(s, first[i] + jj, first[i] + j1, first[k], m);
      else quad(s, first[i] + jj, first[i] + j1, first[k] + j1, first[k] + jj, m);
    }
  }
  if (smooth) smooth_normals(s, v0, t0);
}

void add_round_cylinder(Scene& s, Vec3 a, Vec3 b, float r, int segments, uint32_t m, bool smooth, bool caps) {
  float h = length(b - a);
  if (caps) add_lathe(s, a, b - a, {{0, 0}, {r, 0}, {r, 0}, {r, h}, {r, h}, {0, h}}, segments, m, smooth);
  else add_lathe(s, a, b - a, {{r, 0}, {r, h}}, segments, m, smooth);
}

void add_cone(Scene& s, Vec3 base, float r, float h, int segments, uint32_t m, bool smooth) {
  add_lathe(s, base, {0, 1, 0}, {{0, 0}, {r, 0}, {r, 0}, {0, h}}, segments, m, smooth);
}

void add_sphere(Scene& s, Vec3 c, float r, int segments, uint32_t m, bool smooth) {
  std::vector<ProfilePoint> prof;
  int rings = std::max(2, segments / 2);
  for (int i = 0; i <= rings; ++i) {
    float a = -kPi / 2 + kPi * float(i) / float(rings);
    prof.push_back({i == 0 || i == rings ? 0.0f : r * std::cos(a), r * std::sin(a)});
  }
  add_lathe(s, c, {0, 1, 0}, prof, segments, m, smooth);
}

void add_dome(Scene& s, Vec3 c, float r, int segments, uint32_t m, bool smooth) {
  std::vector<ProfilePoint> prof = {{0, 0}, {r, 0}};  // the floor disc, then a crease
  int rings = std::max(2, segments / 4);
  for (int i = 0; i <= rings; ++i) {
    float a = kPi / 2 * float(i) / float(rings);
    prof.push_back({i == rings ? 0.0f : r * std::cos(a), r * std::sin(a)});
  }
  add_lathe(s, c, {0, 1, 0}, prof, segments, m, smooth);
}

void add_torus(Scene& s, Vec3 c, Vec3 axis, float R, float r, int segments, int tube, uint32_t m, bool smooth) {
  std::vector<ProfilePoint> prof;
  for (int i = 0; i < tube; ++i) {
    float a = 2 * kPi * float(i) / float(tube);
    prof.push_back({R + r * std::cos(a), r * std::sin(a)});
  }
  add_lathe(s, c, axis, prof, segments, m, smooth, true);
}

void add_bevelled_box(Scene& s, Vec3 centre, Vec3 half, float bevel, float yaw, uint32_t m, bool smooth,
                      int arc_steps) {
  if (smooth) pad_normals(s);
  float e[3] = {half.x - bevel, half.y - bevel, half.z - bevel};
  // Samples along one tangent axis: (inner offset, tangent slope): the 45-degree half
  // of the rounded edge at each end that belongs to this face, and the flat middle.
  auto samples = [&](int a) {
    std::vector<std::pair<float, float>> out;
    for (int i = 0; i <= arc_steps; ++i) out.push_back({-e[a], -1 + float(i) / float(arc_steps)});
    for (int i = 0; i <= arc_steps; ++i) out.push_back({e[a], float(i) / float(arc_steps)});
    return out;
  };
  float cy = std::cos(yaw), sy = std::sin(yaw);
  auto world = [&](Vec3 p) { return Vec3(cy * p.x + sy * p.z, p.y, -sy * p.x + cy * p.z); };
  for (int k = 0; k < 3; ++k)
    for (float sign : {-1.0f, 1.0f}) {
      int u = (k + 1) % 3, v = (k + 2) % 3;
      auto su = samples(u), sv = samples(v);
      uint32_t b = uint32_t(s.positions.size());
      for (auto& [iv, tv] : sv)
        for (auto& [iu, tu] : su) {
          float comp[3], t[3];
          comp[k] = sign * e[k], t[k] = sign;
          comp[u] = iu, t[u] = tu;
          comp[v] = iv, t[v] = tv;
          // Same expression, same order for a seam vertex reached from either face.
          float len = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
          Vec3 d(t[0] / len, t[1] / len, t[2] / len);
          Vec3 p(comp[0] + bevel * d.x, comp[1] + bevel * d.y, comp[2] + bevel * d.z);
          s.positions.push_back(centre + world(p));
          if (smooth) s.normals.push_back(world(d));
        }
      uint32_t nu = uint32_t(su.size());
      for (uint32_t j = 0; j + 1 < sv.size(); ++j)
        for (uint32_t i = 0; i + 1 < nu; ++i)
          quad(s, b + j * nu + i, b + j * nu + i + 1, b + (j + 1) * nu + i + 1, b + (j + 1) * nu + i, m);
    }
}

void add_displaced_sphere(Scene& s, Vec3 c, Vec3 radii, int levels, const std::function<float(Vec3)>& displace,
                          uint32_t m, bool smooth) {
  // Icosahedron, then each triangle split in four with shared midpoints.
  const float g = (1 + std::sqrt(5.0f)) / 2;
  std::vector<Vec3> v = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                         {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  for (auto& p : v) p = normalize(p);
  std::vector<std::array<uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(normalize(v[a] + v[b]));
      return mid[key] = uint32_t(v.size() - 1);
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (auto& t : f) {
      uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), d = midpoint(t[2], t[0]);
      next.push_back({t[0], a, d});
      next.push_back({t[1], b, a});
      next.push_back({t[2], d, b});
      next.push_back({a, b, d});
    }
    f = std::move(next);
  }
  if (smooth) pad_normals(s);
  const uint32_t v0 = uint32_t(s.positions.size());
  const size_t t0 = s.triangles.size();
  for (Vec3 d : v) s.positions.push_back(c + radii * d * std::max(0.05f, 1 + displace(d)));
  for (auto& t : f) tri(s, v0 + t[0], v0 + t[1], v0 + t[2], m);
  if (smooth) smooth_normals(s, v0, t0);
}

void add_height_field(Scene& s, float x0, float x1, float z0, float z1, int nx, int nz,
                      const std::function<float(float, float)>& height, uint32_t m, bool smooth) {
  if (smooth) pad_normals(s);
  const uint32_t v0 = uint32_t(s.positions.size());
  const size_t t0 = s.triangles.size();
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i) {
      float x = x0 + (x1 - x0) * float(i) / float(nx), z = z0 + (z1 - z0) * float(j) / float(nz);
      s.positions.push_back({x, height(x, z), z});
    }
  uint32_t w = uint32_t(nx + 1);
  for (uint32_t j = 0; j < uint32_t(nz); ++j)
    for (uint32_t i = 0; i < uint32_t(nx); ++i)
      quad(s, v0 + j * w + i, v0 + j * w + i + 1, v0 + (j + 1) * w + i + 1, v0 + (j + 1) * w + i, m);
  if (smooth) smooth_normals(s, v0, t0);
}

void add_band_extrusion(Scene& s, const std::vector<ProfilePoint>& outer, const std::vector<ProfilePoint>& inner,
                        Vec3 origin, Vec3 eu, Vec3 ev, Vec3 depth, uint32_t m, bool smooth_inner, bool smooth_outer) {
  size_t n = std::min(outer.size(), inner.size());
  if (n < 2) return;
  auto at = [&](const ProfilePoint& p, bool back) { return origin + eu * p.r + ev * p.y + (back ? depth : Vec3()); };
  // End faces: the strip between the polylines, at the front and at the back.
  for (bool back : {false, true}) {
    uint32_t b = uint32_t(s.positions.size());
    for (size_t i = 0; i < n; ++i) s.positions.push_back(at(outer[i], back)), s.positions.push_back(at(inner[i], back));
    for (uint32_t i = 0; i + 1 < n; ++i) quad(s, b + 2 * i, b + 2 * i + 2, b + 2 * i + 3, b + 2 * i + 1, m);
  }
  // Walls along each polyline; each has its own vertices so its normals do not blend
  // with the end faces'.
  for (int w = 0; w < 2; ++w) {
    const auto& line = w == 0 ? inner : outer;
    bool smooth = w == 0 ? smooth_inner : smooth_outer;
    if (smooth) pad_normals(s);
    const uint32_t v0 = uint32_t(s.positions.size());
    const size_t t0 = s.triangles.size();
    for (size_t i = 0; i < n; ++i) s.positions.push_back(at(line[i], false)), s.positions.push_back(at(line[i], true));
    for (uint32_t i = 0; i + 1 < n; ++i) quad(s, v0 + 2 * i, v0 + 2 * i + 2, v0 + 2 * i + 3, v0 + 2 * i + 1, m);
    if (smooth) smooth_normals(s, v0, t0);
  }
  // The two end walls closing the band.
  for (size_t i : {size_t(0), n - 1}) {
    Vec3 a = at(outer[i], false), b = at(inner[i], false);
    add_quad(s, a, b - a, depth, m);
  }
}

void add_groin_vault(Scene& s, Vec3 c, float R, int steps, uint32_t m, bool smooth) {
  // Web of the vault whose axis is x (swap = false) or z (swap = true), on the side
  // sign * (axis coordinate) > 0: parameter phi runs around the barrel, t from the
  // groin (|axis coordinate| = |across coordinate|) out to the bay's edge.
  for (bool swap : {false, true})
    for (float sign : {-1.0f, 1.0f}) {
      if (smooth) pad_normals(s);
      uint32_t b = uint32_t(s.positions.size());
      for (int i = 0; i <= steps; ++i) {
        float phi = kPi * float(i) / float(steps);
        float across = R * std::cos(phi), y = R * std::sin(phi);
        for (int j = 0; j <= steps; ++j) {
          float t = float(j) / float(steps);
          float along = sign * (std::fabs(across) + (R - std::fabs(across)) * t);
          Vec3 p = swap ? Vec3(across, y, along) : Vec3(along, y, across);
          s.positions.push_back(c + p);
          if (smooth) s.normals.push_back(swap ? Vec3(-across / R, -y / R, 0) : Vec3(0, -y / R, -across / R));
        }
      }
      uint32_t w = uint32_t(steps + 1);
      for (uint32_t i = 0; i < uint32_t(steps); ++i)
        for (uint32_t j = 0; j < uint32_t(steps); ++j)
          quad(s, b + i * w + j, b + i * w + j + 1, b + (i + 1) * w + j + 1, b + (i + 1) * w + j, m);
    }
}

}  // namespace nns::render
