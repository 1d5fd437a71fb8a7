#pragma once
// Scene: what the ground-truth renderer draws. Plain data, no Embree: one triangle soup
// with a material per triangle, plus the analytic lights and the sky.
//
// Units and radiometry (docs/renderer.md): every light colour is given as the radiance
// a white Lambertian surface facing the light reflects, i.e. irradiance / pi, which is
// the number a rasterizer multiplies by albedo * cos. Emission is emitted radiance.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "render/material_texture.h"
#include "core/vec3.h"

namespace nns::render {

struct Material {
  Vec3 albedo{0.7f, 0.7f, 0.7f};  // diffuse reflectance in [0, 1): the base under any texture
  Vec3 emission{0, 0, 0};         // emitted radiance, both sides of the surface
  MaterialTexture texture;        // kind none: albedo everywhere
  // A constructor rather than an aggregate, so the families' {albedo, emission} stays
  // warning-free with the texture left out.
  Material(Vec3 a = {0.7f, 0.7f, 0.7f}, Vec3 e = {0, 0, 0}, MaterialTexture t = {})
      : albedo(a), emission(e), texture(t) {}
};
static_assert(sizeof(Material) == 24 + sizeof(MaterialTexture), "Material must have no padding bytes");

// The albedo of material m at world point p, normal n: every reader of a surface's
// reflectance (the G-buffer, each bounce of the integrator) goes through this.
inline Vec3 surface_albedo(const Material& m, Vec3 p, Vec3 n) {
  return m.texture.kind == TextureKind::none ? m.albedo : textured_albedo(m.texture, m.albedo, p, n);
}

struct Triangle {
  std::array<uint32_t, 3> v;
  uint32_t material;
};

// Directional light. `direction` points from the surface towards the sun.
struct Sun {
  Vec3 direction{0, 1, 0};
  Vec3 color{0, 0, 0};       // E_perpendicular / pi
  float angular_radius = 0;  // radians; 0 = a hard-shadow point sun
};

// Isotropic point light: direct = color * cos / d^2 (color = intensity / pi).
struct PointLight {
  Vec3 position;
  Vec3 color;
};

// One-sided rectangle corner + [0,1]^2 * (edge_u, edge_v), emitting radiance `radiance`
// towards cross(edge_u, edge_v). It is a light, not geometry: rays do not hit it
// (an emissive surface that rays should see is a Material with emission).
struct RectLight {
  Vec3 corner, edge_u, edge_v;
  Vec3 radiance;
};

// Sky radiance by direction: zenith..horizon blend above the horizon, `ground` below.
// A constant sky has all three equal.
struct Sky {
  Vec3 zenith{0, 0, 0}, horizon{0, 0, 0}, ground{0, 0, 0};
  Vec3 radiance(Vec3 dir) const {
    if (dir.y < 0) return ground;
    return lerp(horizon, zenith, std::sqrt(dir.y));
  }
  static Sky constant(Vec3 c) { return {c, c, c}; }
};

// Where placement may put cameras (an axis-aligned box) and where they may look:
// yaw as in Camera::from_yaw_pitch (0 looks down -z), within yaw_range_deg/2 of the
// centre (360 = any direction).
struct CameraRegion {
  Vec3 min{-1, 0.5f, -1}, max{1, 2, 1};
  float pitch_min_deg = -30, pitch_max_deg = 15;
  float yaw_center_deg = 0, yaw_range_deg = 360;
};

struct Scene {
  std::string name;  // the dataset's `scene` attribute: family-instance or file stem
  std::vector<Vec3> positions;
  // Per-vertex shading normals (render/scenes/mesh_builder.h): empty, or one per
  // position. A triangle whose three vertex normals are non-zero is shaded with their
  // barycentric interpolation (smooth curved surfaces); a zero normal at any of its
  // vertices keeps it flat, so faceted and smooth parts share one vertex array.
  std::vector<Vec3> normals;
  std::vector<Triangle> triangles;
  std::vector<Material> materials;
  std::vector<Sun> suns;
  std::vector<PointLight> points;
  std::vector<RectLight> rects;
  Sky sky;
  CameraRegion cameras;
  float ao_radius = 1.0f;  // the world-space radius AO is computed for (`aoRadius`)

  uint32_t add_material(Material m) {
    materials.push_back(m);
    return uint32_t(materials.size() - 1);
  }
  void bounds(Vec3& lo, Vec3& hi) const {
    lo = Vec3(1e30f);
    hi = Vec3(-1e30f);
    for (auto& p : positions) lo = vmin(lo, p), hi = vmax(hi, p);
  }
};

}  // namespace nns::render
