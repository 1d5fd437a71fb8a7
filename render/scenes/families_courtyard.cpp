// Generation-3 outdoor family: a courtyard open to the sky, enclosed by four wings of
// 2-4 storeys with arcades, eaves, balconies, recessed windows and doors, and a passage
// through one wing to the street outside. The buildings are the sky and sun occluders:
// the sun falls into part of the court, the arcades and the far corners live on sky
// and bounce light.
#include "render/scenes/families.h"
#include "render/scenes/family_kit.h"
#include "render/scenes/wing_frame.h"

namespace nns::render {

namespace {
struct Materials {
  uint32_t plaster, roof, stone, glass, wood, iron;
};

// One storey of openings along [-span, span] at the wall line u: windows (and, on the
// ground, doors), each closed by a recessed panel; `skip` is a passage's interval.
std::vector<Opening> storey_openings(Scene& s, Rng& rng, const Wing& w, float u, float span, float y0, float fh,
                                     bool ground, Opening skip, const Materials& m) {
  std::vector<Opening> holes;
  const int cols = std::max(1, int(2 * span / float(rng.uniform(2.2, 3.2))));
  const float step = 2 * span / float(cols);
  for (int i = 0; i < cols; ++i) {
    float vc = -span + step * (float(i) + 0.5f), ww = std::min(step - 0.6f, float(rng.uniform(0.7, 1.3)));
    if (ww < 0.4f || rng.below(100) < 15) continue;
    bool door = ground && rng.below(3) == 0;
    Opening o{vc - ww / 2, vc + ww / 2, y0 + (door ? 0.0f : float(rng.uniform(0.7, 1.0))),
              y0 + std::min(fh - 0.5f, 2.3f)};
    if (o.a1 > skip.a0 - 0.3f && o.a0 < skip.a1 + 0.3f) continue;
    holes.push_back(o);
    w.box(s, u + 0.12f, o.y0, o.a0, u + 0.2f, o.y1, o.a1, door ? m.wood : m.glass);
    if (!ground && !door && rng.below(100) < 15) {  // a balcony: slab, rail, posts
      w.box(s, u - 1.1f, o.y0 - 0.12f, o.a0 - 0.3f, u - 0.2f, o.y0, o.a1 + 0.3f, m.stone);
      for (float v : {o.a0 - 0.28f, 0.5f * (o.a0 + o.a1), o.a1 + 0.28f})
        add_beam(s, w.at(u - 1.05f, o.y0, v), w.at(u - 1.05f, o.y0 + 0.95f, v), 0.04f, m.iron);
      add_beam(s, w.at(u - 1.05f, o.y0 + 0.95f, o.a0 - 0.3f), w.at(u - 1.05f, o.y0 + 0.95f, o.a1 + 0.3f), 0.05f,
               m.iron);
    }
  }
  if (skip.a1 > skip.a0) {
    holes.push_back(skip);
    std::sort(holes.begin(), holes.end(), [](const Opening& a, const Opening& b) { return a.a0 < b.a0; });
  }
  return holes;
}
}  // namespace

// The court itself: paving, a fountain, planters, benches; cameras stand in it.
Scene make_courtyard(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  Materials m;
  m.plaster = s.add_material(random_material(rng, 0.45f, 0.85f));
  m.roof = s.add_material(random_material(rng, 0.2f, 0.5f));
  m.stone = s.add_material(random_material(rng, 0.4f, 0.8f));
  m.glass = s.add_material(random_material(rng, 0.05f, 0.25f));
  m.wood = s.add_material(random_material(rng, 0.15f, 0.5f));
  m.iron = s.add_material(random_material(rng, 0.05f, 0.3f));
  add_quad(s, {-80, 0, -80}, {160, 0, 0}, {0, 0, 160}, s.add_material(random_material(rng, 0.25f, 0.6f)));
  const float cx = float(rng.uniform(4, 9)), cz = float(rng.uniform(4, 9)), depth = float(rng.uniform(5, 8));
  const float fh = float(rng.uniform(3.0, 3.6));
  int storeys[4];
  for (int& n : storeys) n = 2 + int(rng.below(3));
  const int passage_wing = rng.below(10) < 6 ? int(rng.below(4)) : -1;
  for (int k = 0; k < 4; ++k) {
    Wing w{k, k % 2 ? cz : cx};
    const float span = k % 2 ? cx : cz;              // the courtyard part of the facade: v in [-span, span]
    const float vmax = k % 2 ? span : span + depth;  // x-wings take the corners
    const float H = fh * float(storeys[k]);
    const bool arcade = rng.below(2) != 0;
    const float ad = float(rng.uniform(2.0, 3.2)), eave = rng.below(3) ? float(rng.uniform(0.4, 1.5)) : 0.0f;
    const float ground_u = arcade ? ad : 0;
    Opening passage{0, 0, 0, 0};
    if (k == passage_wing) {
      float pw = float(rng.uniform(2.5, 4)), vc = float(rng.uniform(-span + pw / 2 + 0.6, span - pw / 2 - 0.6));
      passage = {vc - pw / 2, vc + pw / 2, 0, float(rng.uniform(2.5, fh - 0.4))};
      for (float v : {passage.a0 - 0.2f, passage.a1 + 0.2f})  // the tunnel's sides, its ceiling
        w.box(s, ground_u + 0.2f, 0, v - 0.2f, depth - 0.2f, fh, v + 0.2f, m.plaster);
      w.box(s, ground_u + 0.2f, passage.y1, passage.a0, depth - 0.2f, passage.y1 + 0.2f, passage.a1, m.plaster);
    }
    // Ground storey: the facade, or an arcade's back wall behind a row of columns.
    w.wall(s, ground_u, -span, span, 0, fh, storey_openings(s, rng, w, ground_u, span, 0, fh, true, passage, m),
           m.plaster);
    if (vmax > span)
      for (float sgn : {-1.0f, 1.0f})
        w.wall(s, 0, std::min(sgn * span, sgn * vmax), std::max(sgn * span, sgn * vmax), 0, fh, {}, m.plaster);
    if (arcade) {
      for (float sgn : {-1.0f, 1.0f})
        w.box(s, -0.2f, 0, sgn * span - 0.2f, ad + 0.2f, fh, sgn * span + 0.2f, m.plaster);
      w.box(s, -0.3f, fh - 0.35f, -span, ad, fh, span, m.stone);  // the walkway's ceiling
      const int bays = std::max(2, int(2 * span / float(rng.uniform(2.2, 3.4))));
      const bool round = rng.below(3) != 0;
      const float r = float(rng.uniform(0.14, 0.26));
      for (int i = 1; i < bays; ++i) {
        float v = -span + 2 * span * float(i) / float(bays);
        if (round) add_round_cylinder(s, w.at(0, 0, v), w.at(0, fh - 0.35f, v), r, st.segments(20), m.stone, st.smooth);
        else w.box(s, -r, 0, v - r, r, fh - 0.35f, v + r, m.stone);
      }
    }
    // Upper storeys, the outer wall (with the passage's far end), the ends, the roof and its eave.
    for (int j = 1; j < storeys[k]; ++j)
      w.wall(s, 0, -vmax, vmax, fh * float(j), fh * float(j + 1),
             storey_openings(s, rng, w, 0, span, fh * float(j), fh, false, {0, 0, 0, 0}, m), m.plaster);
    std::vector<Opening> far;
    if (k == passage_wing) far.push_back(passage);
    w.wall(s, depth, -vmax, vmax, 0, H, far, m.plaster);
    const int left = k % 2 ? (k == 1 ? 0 : 2) : -1,
              right = k % 2 ? (k == 1 ? 2 : 0) : -1;  // the x-wings beside a z-wing
    for (float sgn : {-1.0f, 1.0f}) {
      // An x-wing closes its own ends; a z-wing's ends are the x-wings' walls, up to their height.
      float below = k % 2 ? fh * float(storeys[sgn < 0 ? left : right]) : 0.0f;
      if (H > below) w.box(s, -0.2f, below, sgn * vmax - 0.2f, depth, H, sgn * vmax + 0.2f, m.plaster);
    }
    w.box(s, -0.2f - eave, H, -vmax - 0.2f, depth + 0.2f, H + 0.3f, vmax + 0.2f, m.roof);
  }
  // The court: a fountain, planters with shrubs, benches, a few things lying about.
  if (rng.below(2)) {
    float R = float(rng.uniform(0.8, std::min(cx, cz) * 0.35));
    add_lathe(s, {0, 0, 0}, {0, 1, 0},
              {{0, 0.3f}, {R - 0.15f, 0.3f}, {R - 0.15f, 0.55f}, {R - 0.15f, 0.55f}, {R, 0.55f}, {R, 0.55f}, {R, 0}},
              st.segments(32), m.stone, st.smooth);
    add_round_cylinder(s, {0, 0.3f, 0}, {0, 1.4f, 0}, 0.12f, st.segments(12), m.stone, st.smooth);
  }
  for (int k = scaled_count(4, st.density); k > 0; --k) {
    Vec3 c(float(rng.uniform(-cx + 1, cx - 1)), 0, float(rng.uniform(-cz + 1, cz - 1)));
    if (std::fabs(c.x) < 1.6f && std::fabs(c.z) < 1.6f) continue;  // the fountain's place
    switch (rng.below(3)) {
      case 0: {  // planter and shrub
        float hw = float(rng.uniform(0.3, 0.6));
        add_box(s, c - Vec3(hw, 0, hw), c + Vec3(hw, 0.5f, hw), m.stone);
        uint64_t shrub = rng.next_u64();
        add_displaced_sphere(
            s, c + Vec3(0, 0.5f + hw * 0.7f, 0), {hw * 1.1f, hw * 0.9f, hw * 1.1f}, 3,
            [shrub](Vec3 p) { return 0.25f * fbm(shrub, p * 3.0f, 3); },
            s.add_material(random_material(rng, 0.1f, 0.4f)), st.smooth);
        break;
      }
      case 1:  // a bench
        add_table(s, c, float(rng.uniform(1.2, 2.0)), 0.45f, 0.45f, float(rng.below(2)) * kPi / 2, m.wood);
        break;
      default:
        add_random_object(s, rng, c.x, c.z, 0, float(rng.uniform(0.3, 0.9)) * st.scale, st);
    }
  }
  outdoor_lighting(s, rng, 25, 70);
  s.cameras = {{-cx + 0.5f, 1.0f, -cz + 0.5f}, {cx - 0.5f, 2.4f, cz - 0.5f}, -30, 25};
  return s;
}

}  // namespace nns::render
