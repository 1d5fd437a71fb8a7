#pragma once
// Floor plans for the generation-3 interiors (corridor, multiroom): rectangular spaces
// that tile part of the ground without overlapping, with walls centred on their edges.
// A wall line shared by two spaces is built once (the intervals of every space on a
// line are merged), walls run half their thickness past each end so corners close,
// and openings (doorways between spaces, windows and doors to the outside, a corridor
// junction left fully open) are holes cut into those lines.
#include <optional>
#include <vector>

#include "render/scenes/family_util.h"

namespace nns::render {

struct PlanRect {
  float x0, z0, x1, z1;  // a space's edges = its walls' centre lines
  float cx() const { return 0.5f * (x0 + x1); }
  float cz() const { return 0.5f * (z0 + z1); }
};

// An interval [lo, hi] on a wall line: z = plane (along_x) or x = plane.
struct WallSpan {
  bool along_x;
  float plane, lo, hi;
};

struct WallHole {
  bool along_x;
  float plane;
  Opening o;  // o.a0..o.a1 along the line, o.y0..o.y1
};

struct FloorPlan {
  std::vector<PlanRect> spaces;
  std::vector<WallHole> holes;
  float thick = 0.15f;  // every wall's thickness
  float height = 2.8f;  // floor to ceiling
};

// The edge spaces a and b share, when it is at least `min_len` long.
std::optional<WallSpan> shared_edge(const PlanRect& a, const PlanRect& b, float min_len = 0);

// The parts of space i's edges that no other space shares: its walls to the outside.
std::vector<WallSpan> outer_edges(const FloorPlan& p, size_t i);

// A hole of width `w` (clamped to the span) centred at a random point of `span`,
// keeping `margin` from its ends; none when the span is too short.
std::optional<WallHole> hole_in(const WallSpan& span, Rng& rng, float w, float y0, float y1, float margin);

// Every wall of the plan (wall material), with the holes cut; a floor slab under and a
// roof slab over every space, grown by the wall thickness so that neighbouring slabs
// overlap (same material, no seam for sunlight to slip through).
void build_plan(Scene& s, const FloorPlan& p, uint32_t wall, uint32_t floor, uint32_t roof);

// The interior of space i (inside its walls), shrunk by `margin`.
inline PlanRect interior(const FloorPlan& p, size_t i, float margin = 0) {
  const PlanRect& r = p.spaces[i];
  float m = p.thick / 2 + margin;
  return {r.x0 + m, r.z0 + m, r.x1 - m, r.z1 - m};
}

}  // namespace nns::render
