#include "render/scenes/floor_plan.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

namespace nns::render {

namespace {
// The four edges of a space, as spans on their lines.
std::vector<WallSpan> edges_of(const PlanRect& r) {
  return {{true, r.z0, r.x0, r.x1}, {true, r.z1, r.x0, r.x1}, {false, r.x0, r.z0, r.z1}, {false, r.x1, r.z0, r.z1}};
}
}  // namespace

std::optional<WallSpan> shared_edge(const PlanRect& a, const PlanRect& b, float min_len) {
  auto overlap = [&](bool along_x, float plane, float a0, float a1, float b0, float b1) -> std::optional<WallSpan> {
    float lo = std::max(a0, b0), hi = std::min(a1, b1);
    if (hi - lo < std::max(min_len, 1e-3f)) return std::nullopt;
    return WallSpan{along_x, plane, lo, hi};
  };
  if (a.z1 == b.z0 || a.z0 == b.z1) return overlap(true, a.z1 == b.z0 ? a.z1 : a.z0, a.x0, a.x1, b.x0, b.x1);
  if (a.x1 == b.x0 || a.x0 == b.x1) return overlap(false, a.x1 == b.x0 ? a.x1 : a.x0, a.z0, a.z1, b.z0, b.z1);
  return std::nullopt;
}

std::vector<WallSpan> outer_edges(const FloorPlan& p, size_t i) {
  std::vector<WallSpan> out;
  for (const WallSpan& e : edges_of(p.spaces[i])) {
    // What the other spaces cover of this edge, then the gaps between those covers.
    std::vector<std::pair<float, float>> covered;
    for (size_t j = 0; j < p.spaces.size(); ++j)
      if (j != i)
        for (const WallSpan& f : edges_of(p.spaces[j]))
          if (f.along_x == e.along_x && f.plane == e.plane && f.hi > e.lo && f.lo < e.hi)
            covered.emplace_back(std::max(f.lo, e.lo), std::min(f.hi, e.hi));
    std::sort(covered.begin(), covered.end());
    float u = e.lo;
    for (auto [lo, hi] : covered) {
      if (lo - u > 1e-3f) out.push_back({e.along_x, e.plane, u, lo});
      u = std::max(u, hi);
    }
    if (e.hi - u > 1e-3f) out.push_back({e.along_x, e.plane, u, e.hi});
  }
  return out;
}

std::optional<WallHole> hole_in(const WallSpan& span, Rng& rng, float w, float y0, float y1, float margin) {
  float room = span.hi - span.lo - 2 * margin;
  w = std::min(w, room);
  if (w < 0.5f) return std::nullopt;
  float c = float(rng.uniform(span.lo + margin + w / 2, span.hi - margin - w / 2));
  return WallHole{span.along_x, span.plane, {c - w / 2, c + w / 2, y0, y1}};
}

void build_plan(Scene& s, const FloorPlan& p, uint32_t wall, uint32_t floor, uint32_t roof) {
  const float t = p.thick;
  // Every line's intervals (a std::map: lines in a fixed order), merged.
  std::map<std::pair<bool, float>, std::vector<std::pair<float, float>>> lines;
  for (const PlanRect& r : p.spaces)
    for (const WallSpan& e : edges_of(r)) lines[{e.along_x, e.plane}].emplace_back(e.lo - t / 2, e.hi + t / 2);
  for (auto& [line, spans] : lines) {
    std::sort(spans.begin(), spans.end());
    std::vector<std::pair<float, float>> merged;
    for (auto sp : spans) {
      if (!merged.empty() && sp.first <= merged.back().second)
        merged.back().second = std::max(merged.back().second, sp.second);
      else merged.push_back(sp);
    }
    for (auto [lo, hi] : merged) {
      std::vector<Opening> holes;
      for (const WallHole& h : p.holes)
        if (h.along_x == line.first && h.plane == line.second && h.o.a0 >= lo && h.o.a1 <= hi) holes.push_back(h.o);
      std::sort(holes.begin(), holes.end(), [](const Opening& a, const Opening& b) { return a.a0 < b.a0; });
      for (size_t k = 1; k < holes.size(); ++k)
        if (holes[k].a0 < holes[k - 1].a1) throw std::logic_error("build_plan: overlapping openings on a wall line");
      add_wall_band(s, line.first, line.second, lo, hi, 0, p.height, t, holes, wall);
    }
  }
  for (const PlanRect& r : p.spaces) {
    add_box(s, {r.x0 - t / 2, -0.1f, r.z0 - t / 2}, {r.x1 + t / 2, 0, r.z1 + t / 2}, floor);
    add_box(s, {r.x0 - t / 2, p.height, r.z0 - t / 2}, {r.x1 + t / 2, p.height + 0.2f, r.z1 + t / 2}, roof);
  }
}

}  // namespace nns::render
