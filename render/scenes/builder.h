#pragma once
// Geometry helpers for building Scenes out of quads, boxes and prisms. Every surface
// is two-sided (the ray tracer faces normals towards the ray), so winding is free.
#include <cstdint>

#include "render/scene.h"

namespace nns::render {

// Parallelogram p, p+e1, p+e1+e2, p+e2.
void add_quad(Scene& s, Vec3 p, Vec3 e1, Vec3 e2, uint32_t material);
// Axis-aligned box, all six faces.
void add_box(Scene& s, Vec3 lo, Vec3 hi, uint32_t material);
// Box of half-size `half` centred at `centre`, turned by `yaw` radians about +y.
void add_box_yaw(Scene& s, Vec3 centre, Vec3 half, float yaw, uint32_t material);
// Vertical prism (a cylinder with `sides` faces) standing on `base`, with caps.
void add_cylinder(Scene& s, Vec3 base, float radius, float height, int sides, uint32_t material);
// Box between two points with a square cross-section of side `thickness` (beams,
// railings, poles at any angle).
void add_beam(Scene& s, Vec3 a, Vec3 b, float thickness, uint32_t material);

}  // namespace nns::render
