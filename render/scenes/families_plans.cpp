// Generation-3 interiors built on floor plans (floor_plan.h): corridors with side
// rooms, niches and beams that turn or meet a cross corridor lit from outside, and
// flats of 3-6 rooms joined by doorways, lamps in some rooms only. Both are about
// light that reaches the visible space from somewhere the camera cannot see.
#include "render/scenes/families.h"
#include "render/scenes/family_kit.h"
#include "render/scenes/floor_plan.h"

namespace nns::render {

namespace {
// Windows along an outside wall: the span cut into pieces of about 3 m, each with
// probability `share` a window of its own.
void add_windows(FloorPlan& p, const WallSpan& span, Rng& rng, float share) {
  int pieces = std::max(1, int((span.hi - span.lo) / 3.0f));
  float step = (span.hi - span.lo) / float(pieces);
  for (int k = 0; k < pieces; ++k) {
    if (rng.uniform() >= share) continue;
    WallSpan piece{span.along_x, span.plane, span.lo + step * float(k), span.lo + step * float(k + 1)};
    float sill = float(rng.uniform(0.5, 1.0)), top = std::min(p.height - 0.25f, float(rng.uniform(2.0, 2.4)));
    if (auto h = hole_in(piece, rng, float(rng.uniform(0.8, 2.2)), sill, top, p.thick / 2 + 0.2f))
      p.holes.push_back(*h);
  }
}

// A door between two spaces (or to the outside): a door leaf's size, or now and then
// a wide opening almost to the ceiling.
std::optional<WallHole> add_doorway(FloorPlan& p, const WallSpan& span, Rng& rng) {
  bool wide = rng.below(10) < 3;
  float w = wide ? float(rng.uniform(1.4, 2.6)) : float(rng.uniform(0.8, 1.2));
  float top = wide ? p.height - float(rng.uniform(0.2, 0.5)) : std::min(p.height - 0.2f, float(rng.uniform(2.0, 2.3)));
  auto h = hole_in(span, rng, w, 0, top, p.thick / 2 + 0.15f);
  if (h) p.holes.push_back(*h);
  return h;
}

// A keep-out box in front of and behind a doorway, so furniture does not block it.
struct KeepOut {
  float x0, z0, x1, z1;
};
KeepOut keep_out(const WallHole& h) {
  if (h.along_x) return {h.o.a0 - 0.3f, h.plane - 1.0f, h.o.a1 + 0.3f, h.plane + 1.0f};
  return {h.plane - 1.0f, h.o.a0 - 0.3f, h.plane + 1.0f, h.o.a1 + 0.3f};
}

// A free spot for something of radius r in `room`, or none after a few tries.
std::optional<Vec3> free_spot(Rng& rng, const PlanRect& room, float r, const std::vector<KeepOut>& keep) {
  for (int tries = 0; tries < 8; ++tries) {
    if (room.x1 - room.x0 < 2 * r || room.z1 - room.z0 < 2 * r) return std::nullopt;
    Vec3 c(float(rng.uniform(room.x0 + r, room.x1 - r)), 0, float(rng.uniform(room.z0 + r, room.z1 - r)));
    bool clear = true;
    for (const KeepOut& k : keep) clear &= c.x + r < k.x0 || c.x - r > k.x1 || c.z + r < k.z0 || c.z - r > k.z1;
    if (clear) return c;
  }
  return std::nullopt;
}

// Furniture-like clutter for one room: a sitting corner, a dining table, a storeroom
// of generated objects, or a bit of each.
void furnish_room(Scene& s, Rng& rng, const PlanRect& room, const std::vector<KeepOut>& keep, const SceneStyle& st) {
  int kind = int(rng.below(4));
  if (kind == 0 || kind == 3) {
    if (auto c = free_spot(rng, room, 1.1f, keep))
      add_sofa(s, rng, *c, float(rng.uniform(0.9, 2.0)), float(rng.below(4)) * kPi / 2,
               s.add_material(random_material(rng, 0.2f, 0.7f)), st);
    if (auto c = free_spot(rng, room, 0.8f, keep)) {
      float r = float(rng.uniform(0.3, 0.6)), th = float(rng.uniform(0.45, 0.75));
      add_round_table(s, *c, r, th, s.add_material(random_material(rng)), st);
      for (int i = int(rng.below(3)); i > 0; --i)
        add_turned_object(s, rng, *c + Vec3(float(rng.uniform(-r / 2, r / 2)), th, float(rng.uniform(-r / 2, r / 2))),
                          float(rng.uniform(0.04, 0.1)), float(rng.uniform(0.1, 0.35)),
                          s.add_material(random_material(rng)), st);
    }
  }
  if (kind == 1 || kind == 3) {
    if (auto c = free_spot(rng, room, 1.2f, keep)) {
      uint32_t m = s.add_material(random_material(rng));
      float w = float(rng.uniform(1.0, 1.8)), d = float(rng.uniform(0.7, 1.0)), yaw = float(rng.below(2)) * kPi / 2;
      add_table(s, *c, w, d, 0.75f, yaw, m);
      for (int i = 2 + int(rng.below(3)); i > 0; --i) {
        float a = float(rng.uniform(0, 2 * kPi));
        add_round_chair(s, *c + Vec3(std::cos(a), 0, std::sin(a)) * (w * 0.5f + 0.25f), kPi / 2 - a, m, st);
      }
    }
  }
  int objects = kind == 2 ? scaled_count(8, st.density) : scaled_count(2, st.density);
  for (int k = 0; k < objects; ++k) {
    float size = float(std::exp(rng.uniform(std::log(0.15), std::log(kind == 2 ? 1.0 : 0.6)))) * st.scale;
    if (auto c = free_spot(rng, room, size / 2 + 0.05f, keep)) {
      float top = add_random_object(s, rng, c->x, c->z, 0, size, st);
      if (kind == 2 && rng.below(3) == 0 && top > 0.1f)
        add_random_object(s, rng, c->x, c->z, top * 0.97f, size * float(rng.uniform(0.3, 0.6)), st);
    }
  }
}

// A lamp for a room: a ceiling panel, or a floor lamp's bulb (a point light on a stand).
void light_room(Scene& s, Rng& rng, const PlanRect& room, float h, const SceneStyle& st) {
  Vec3 c(room.cx() + float(rng.uniform(-0.25, 0.25)) * (room.x1 - room.x0), 0,
         room.cz() + float(rng.uniform(-0.25, 0.25)) * (room.z1 - room.z0));
  if (rng.below(5) < 3) {
    add_lamp_panel(s, c + Vec3(0, h - 0.01f, 0), float(rng.uniform(0.4, 0.9)), kLampRadiance);
    return;
  }
  float lh = float(rng.uniform(1.3, 1.7));
  uint32_t m = s.add_material(random_material(rng, 0.3f, 0.8f));
  add_lathe(s, c, {0, 1, 0},
            {{0, 0}, {0.15f, 0}, {0.15f, 0}, {0.12f, 0.03f}, {0.015f, 0.04f}, {0.015f, lh - 0.1f}, {0, lh - 0.1f}},
            st.segments(16), m, st.smooth);
  s.points.push_back({c + Vec3(0, lh, 0), Vec3(4.0f, 3.5f, 2.7f)});
}
}  // namespace

// A corridor: thick walls with doors into side rooms (some lit, some with windows,
// some furnished) and niches, ceiling beams, lamps along it (some off), and at the far
// end a T-junction or a turn into a cross corridor whose ends open to the sunlit
// outside — the lit patches are round the corner, out of view.
Scene make_corridor(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  FloorPlan p;
  p.thick = float(rng.uniform(0.25, 0.55));
  p.height = float(rng.uniform(2.5, 3.6));
  const float t = p.thick, h = p.height, w = float(rng.uniform(1.6, 3.2)), L = float(rng.uniform(10, 22));
  const float half = (w + t) / 2;
  const int junction = int(rng.below(3));  // 0: a T, 1: a turn to -x, 2: a turn to +x
  const float arm_l = junction != 2 ? float(rng.uniform(4, 9)) : 0,
              arm_r = junction != 1 ? float(rng.uniform(4, 9)) : 0;
  p.spaces = {{-half, -L, half, 0}, {-half - arm_l, -L - (w + t), half + arm_r, -L}};
  p.holes.push_back({true, -L, {-w / 2, w / 2, 0, h}});  // the junction: open
  uint32_t wall = s.add_material(random_material(rng, 0.4f, 0.85f));
  uint32_t floor = s.add_material(random_material(rng, 0.2f, 0.6f));
  uint32_t ceiling = s.add_material(random_material(rng, 0.5f, 0.85f));
  uint32_t wood = s.add_material(random_material(rng, 0.2f, 0.6f));
  add_quad(s, {-60, -0.02f, -60}, {120, 0, 0}, {0, 0, 120}, s.add_material(random_material(rng, 0.2f, 0.5f)));

  // Side rooms tile both sides of the main corridor; each gets a door or niches.
  struct Niche {
    WallHole hole;
    float side;
  };
  std::vector<Niche> niches;
  std::vector<size_t> rooms;
  for (float side : {-1.0f, 1.0f}) {
    const float D = float(rng.uniform(2.5, 5));
    for (float z = 0; z > -L + 0.01f;) {
      float len = float(rng.uniform(2.5, 5));
      if (z - len < -L + 2.0f) len = z + L;
      PlanRect r = side > 0 ? PlanRect{half, z - len, half + D, z} : PlanRect{-half - D, z - len, -half, z};
      rooms.push_back(p.spaces.size());
      p.spaces.push_back(r);
      WallSpan along{false, side * half, z - len, z};
      if (rng.below(4) != 0) {
        add_doorway(p, along, rng);
      } else {
        float sill = float(rng.uniform(0.4, 1.2)), top = std::min(h - 0.3f, sill + float(rng.uniform(0.5, 1.4)));
        if (auto nh = hole_in(along, rng, float(rng.uniform(0.4, 1.2)), sill, top, t / 2 + 0.3f)) {
          p.holes.push_back(*nh);
          niches.push_back({*nh, side});
        }
      }
      z -= len;
    }
  }
  // Doors from the rooms at the far end onto the cross corridor, windows to the outside.
  for (size_t i : rooms)
    if (auto e = shared_edge(p.spaces[i], p.spaces[1], 1.5f); e && rng.below(3) == 0) add_doorway(p, *e, rng);
  for (size_t i = 0; i < p.spaces.size(); ++i)
    for (const WallSpan& e : outer_edges(p, i)) {
      bool arm_end = i == 1 && !e.along_x;  // the ends of the cross corridor open to the outside
      if (arm_end) {
        float top = std::min(h - 0.15f, float(rng.uniform(2.1, 2.8)));
        if (auto hole = hole_in(e, rng, w * float(rng.uniform(0.6, 1.0)), 0, top, t / 2 + 0.1f))
          p.holes.push_back(*hole);
      } else {
        add_windows(p, e, rng, i < 2 ? 0.5f : 0.3f);
      }
    }
  build_plan(s, p, wall, floor, ceiling);

  // Niches: a panel closes each hole part of the way into the wall; now and then a vase in it.
  for (const Niche& n : niches) {
    float depth = t * float(rng.uniform(0.35, 0.65)), face = n.side * w / 2;
    float xa = face + n.side * depth, xb = n.side * (half + t / 2);
    add_box(s, {std::min(xa, xb), n.hole.o.y0, n.hole.o.a0}, {std::max(xa, xb), n.hole.o.y1, n.hole.o.a1}, wall);
    if (rng.below(2))
      add_turned_object(s, rng, {face + n.side * depth / 2, n.hole.o.y0, 0.5f * (n.hole.o.a0 + n.hole.o.a1)},
                        std::min(depth * 0.4f, 0.15f), std::min(n.hole.o.y1 - n.hole.o.y0 - 0.05f, 0.4f),
                        s.add_material(random_material(rng)), st);
  }
  // Ceiling beams across the corridor; lamps between them, some left off.
  const float pitch = float(rng.uniform(1.5, 3.0)), beam_d = float(rng.uniform(0.15, 0.4)),
              beam_w = float(rng.uniform(0.15, 0.3));
  const bool beams = rng.below(10) < 7, lamps = rng.below(10) < 8;
  for (float z = -pitch / 2; z > -L; z -= pitch) {
    if (beams) add_box(s, {-w / 2, h - beam_d, z - beam_w / 2}, {w / 2, h, z + beam_w / 2}, wood);
    if (lamps && z - pitch / 2 > -L && rng.below(10) < 6)
      add_lamp_panel(s, {0, h - 0.01f, z - pitch / 2}, std::min(float(rng.uniform(0.3, 0.6)), pitch - beam_w - 0.1f),
                     kLampRadiance);
  }
  for (size_t i : rooms) {
    PlanRect in = interior(p, i, 0.3f);
    std::vector<KeepOut> keep;
    for (const WallHole& hole : p.holes) keep.push_back(keep_out(hole));
    if (rng.below(2)) light_room(s, rng, in, h, st);
    if (rng.below(3) != 0) furnish_room(s, rng, in, keep, st);
  }
  outdoor_lighting(s, rng, 10, 55);
  s.cameras = {{-w / 2 + 0.35f, 0.8f, -L - w - t / 2 + 0.35f},
               {w / 2 - 0.35f, std::min(1.9f, h - 0.5f), -t / 2 - 0.35f},
               -25,
               20};
  return s;
}

// A flat or an office floor: a rectangle split into 3-6 rooms, every room reachable
// through doorways, furniture-like clutter in each, windows in some outside walls,
// and lamps in some rooms only — the room in view is often lit through a door.
Scene make_multiroom(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  FloorPlan p;
  p.thick = float(rng.uniform(0.1, 0.25));
  p.height = float(rng.uniform(2.5, 3.4));
  const float t = p.thick, h = p.height, W = float(rng.uniform(7, 15)), D = float(rng.uniform(6, 12));
  const int n = 3 + int(rng.below(4));
  const float min_room = 2.4f;
  p.spaces = {{-W / 2, -D / 2, W / 2, D / 2}};
  while (int(p.spaces.size()) < n) {  // split the largest room that can be split, across its longer side
    size_t best = p.spaces.size();
    float area = 0;
    for (size_t i = 0; i < p.spaces.size(); ++i) {
      const PlanRect& r = p.spaces[i];
      float a = (r.x1 - r.x0) * (r.z1 - r.z0);
      if (std::max(r.x1 - r.x0, r.z1 - r.z0) >= 2 * min_room && a > area) best = i, area = a;
    }
    if (best == p.spaces.size()) break;
    PlanRect a = p.spaces[best], b = a;
    const bool cut_x = a.x1 - a.x0 >= a.z1 - a.z0;
    const float lo = cut_x ? a.x0 : a.z0, len = cut_x ? a.x1 - a.x0 : a.z1 - a.z0;
    const float c = lo + len * float(rng.uniform(std::max(0.35f, min_room / len), std::min(0.65f, 1 - min_room / len)));
    if (cut_x) a.x1 = c, b.x0 = c;
    else a.z1 = c, b.z0 = c;
    p.spaces[best] = a;
    p.spaces.push_back(b);
  }
  // Doorways: a random spanning tree over the rooms that share a long enough wall, then
  // a few more.
  const size_t rooms = p.spaces.size();
  std::vector<char> reached(rooms, 0), joined(rooms * rooms, 0);
  reached[0] = 1;
  for (;;) {
    std::vector<std::pair<size_t, size_t>> frontier;
    for (size_t i = 0; i < rooms; ++i)
      for (size_t j = 0; j < rooms; ++j)
        if (reached[i] && !reached[j] && shared_edge(p.spaces[i], p.spaces[j], 1.4f + t)) frontier.emplace_back(i, j);
    if (frontier.empty()) break;
    auto [i, j] = frontier[rng.below(frontier.size())];
    add_doorway(p, *shared_edge(p.spaces[i], p.spaces[j], 1.4f + t), rng);
    reached[j] = 1, joined[i * rooms + j] = joined[j * rooms + i] = 1;
  }
  for (size_t i = 0; i < rooms; ++i)
    for (size_t j = i + 1; j < rooms; ++j)
      if (!joined[i * rooms + j])
        if (auto e = shared_edge(p.spaces[i], p.spaces[j], 1.4f + t); e && rng.below(10) < 3) add_doorway(p, *e, rng);
  for (size_t i = 0; i < rooms; ++i)
    for (const WallSpan& e : outer_edges(p, i)) add_windows(p, e, rng, 0.35f);
  uint32_t wall = s.add_material(random_material(rng, 0.4f, 0.85f));
  uint32_t floor = s.add_material(random_material(rng, 0.2f, 0.6f));
  uint32_t ceiling = s.add_material(random_material(rng, 0.5f, 0.85f));
  add_quad(s, {-60, -0.02f, -60}, {120, 0, 0}, {0, 0, 120}, s.add_material(random_material(rng, 0.2f, 0.5f)));
  build_plan(s, p, wall, floor, ceiling);

  // Lamps in some rooms only: at least one lit and, with three rooms or more, one dark.
  std::vector<char> lit(rooms);
  for (auto& l : lit) l = rng.below(100) < 45;
  if (std::find(lit.begin(), lit.end(), 1) == lit.end()) lit[rng.below(rooms)] = 1;
  if (std::find(lit.begin(), lit.end(), 0) == lit.end()) lit[rng.below(rooms)] = 0;
  std::vector<KeepOut> keep;
  for (const WallHole& hole : p.holes) keep.push_back(keep_out(hole));
  for (size_t i = 0; i < rooms; ++i) {
    PlanRect in = interior(p, i, 0.25f);
    if (lit[i]) light_room(s, rng, in, h, st);
    furnish_room(s, rng, in, keep, st);
  }
  outdoor_lighting(s, rng, 10, 60);
  s.cameras = {{-W / 2 + t / 2 + 0.3f, 0.7f, -D / 2 + t / 2 + 0.3f},
               {W / 2 - t / 2 - 0.3f, std::min(1.8f, h - 0.5f), D / 2 - t / 2 - 0.3f},
               -30,
               15};
  return s;
}

}  // namespace nns::render
