// Generation-4 families: the covered spaces of monumental buildings, where the light in
// view comes through openings out of view. A cloister's walks lit sideways through
// the arcade from a sunlit garth; a basilica's nave and aisles lit from clerestory and
// aisle windows high up, with galleries over the aisles.
#include "render/scenes/arches.h"
#include "render/scenes/families.h"
#include "render/scenes/family_kit.h"
#include "render/scenes/wing_frame.h"

namespace nns::render {

namespace {
// A door in the wall plane u = `u` of a wing (facing -u, towards the walk): a dark
// panel 4 cm proud of the wall in a stone frame 8 cm proud.
void add_door(Scene& s, const Wing& w, float u, float v, float width, float height, uint32_t frame, uint32_t panel) {
  w.box(s, u - 0.08f, 0, v - width / 2 - 0.15f, u, height + 0.15f, v + width / 2 + 0.15f, frame);
  w.box(s, u - 0.12f, 0, v - width / 2, u - 0.08f, height, v + width / 2, panel);
}
// A cloister's garth (half sizes X and Z inside an arcade wall t thick): paths crossing
// it, a well or a tree in the middle, four raised beds now and then.
struct GarthMaterials {
  uint32_t stone, paving, wood;
};
void add_garth(Scene& s, Rng& rng, float X, float Z, float t, GarthMaterials m, const SceneStyle& st) {
  const uint32_t stone = m.stone, paving = m.paving, wood = m.wood;
  const float pw = float(rng.uniform(0.8, 1.5));
  add_box(s, {-X + t / 2, 0, -pw / 2}, {X - t / 2, 0.04f, pw / 2}, paving);
  add_box(s, {-pw / 2, 0, -Z + t / 2}, {pw / 2, 0.04f, Z - t / 2}, paving);
  if (rng.below(2)) {
    const float R = float(rng.uniform(0.6, 1.0));
    add_lathe(s, {0, 0, 0}, {0, 1, 0},
              {{0, 0.05f}, {R - 0.15f, 0.05f}, {R - 0.15f, 0.8f}, {R - 0.15f, 0.8f}, {R, 0.8f}, {R, 0.8f}, {R, 0}},
              st.segments(32), stone, st.smooth);
  } else {
    const float h = float(rng.uniform(2.0, 4.0));
    add_round_cylinder(s, {0, 0, 0}, {0, h, 0}, 0.15f, st.segments(12), wood, st.smooth);
    const uint64_t crown = rng.next_u64();
    const float cr = float(rng.uniform(1.0, std::min(X, Z) * 0.5));
    add_displaced_sphere(
        s, {0, h + cr * 0.6f, 0}, {cr, cr * 0.8f, cr}, 3, [crown](Vec3 p) { return 0.25f * fbm(crown, p * 2.5f, 3); },
        s.add_material(random_material(rng, 0.1f, 0.35f)), st.smooth);
  }
  if (rng.below(2)) {  // four raised beds between the paths
    const uint32_t bed = s.add_material(random_material(rng, 0.1f, 0.3f));
    for (float sx : {-1.0f, 1.0f})
      for (float sz : {-1.0f, 1.0f}) {
        const Vec3 a(sx * (pw / 2 + 0.3f), 0, sz * (pw / 2 + 0.3f));
        const Vec3 c(sx * (X - t / 2 - 0.6f), 0.35f, sz * (Z - t / 2 - 0.6f));
        if ((c.x - a.x) * sx < 0.6f || (c.z - a.z) * sz < 0.6f) continue;
        add_box(s, vmin(a, c), vmax(a, c), bed);
      }
  }
}
}  // namespace

// A cloister: a garth open to the sky (a well or a tree, hedged beds, paths) ringed by
// four covered walks. The walk's garth side is an arcade of columns and round arches,
// on a low parapet in some cloisters; its other side the wall of the buildings round
// it, with doors; overhead groin vaults bay by bay (3 in 5) or a flat ceiling on beams.
// Cameras stand in one walk: the sun and sky come in sideways through the arches, so
// looking along the walk or at its back wall the light source is out of view.
Scene make_cloister(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  const uint32_t stone = s.add_material(random_material(rng, 0.45f, 0.85f));
  const uint32_t plaster = s.add_material(random_material(rng, 0.45f, 0.85f));
  const uint32_t paving = s.add_material(random_material(rng, 0.3f, 0.6f));
  const uint32_t roof = s.add_material(random_material(rng, 0.2f, 0.45f));
  const uint32_t wood = s.add_material(random_material(rng, 0.1f, 0.35f));
  const uint32_t grass = s.add_material(random_material(rng, 0.15f, 0.4f));
  add_quad(s, {-80, 0, -80}, {160, 0, 0}, {0, 0, 160}, grass);
  // The bay b is the arcade's column spacing and the walk's width (square bays, so the
  // groin vaults tile the walks and the corners alike); nx x nz bays of garth.
  const float b = float(rng.uniform(2.4, 3.6)) * st.scale;
  const int nx = 2 + int(rng.below(4)), nz = 2 + int(rng.below(4));
  const float X = b * float(nx) / 2, Z = b * float(nz) / 2;
  const float t = float(rng.uniform(0.45, 0.65));                              // arcade wall thickness
  const float r = float(rng.uniform(0.15, 0.22)) * std::min(st.scale, 1.15f);  // column radius
  const float parapet = rng.below(5) < 2 ? float(rng.uniform(0.5, 0.9)) : 0.0f;
  const float hc = float(rng.uniform(2.0, 2.8)) * st.scale;  // column height
  const float arch_r = b / 2 - 1.4f * r, rise = arch_r + float(rng.uniform(0.25, 0.6));
  const float spring = parapet + hc, arch_top = spring + rise;
  const bool groin = rng.below(5) < 3;
  const float ceiling = groin ? arch_top + float(rng.uniform(0.0, 0.4)) : arch_top + float(rng.uniform(0.2, 0.8));
  const float top = groin ? ceiling + b / 2 + 0.3f : ceiling;  // the walk roof's underside
  const float eave = float(rng.uniform(0.2, 0.9)), depth = float(rng.uniform(4, 8));
  const float building = top + float(rng.uniform(1.0, 7.0));  // the buildings round the cloister
  for (int k = 0; k < 4; ++k) {
    const Wing w{k, k % 2 ? Z : X};
    const float span = k % 2 ? X : Z;             // the arcade runs over v in [-span, span]
    const float reach = k % 2 ? span : span + b;  // x-wings (k even) take the corner bays
    const int bays = k % 2 ? nx : nz;
    // Walk floor, the buildings behind (their face is the walk's back wall), roof.
    w.box(s, -t / 2, 0, -reach, b, 0.12f, reach, paving);
    const float outer = k % 2 ? reach + b : reach + depth;  // z-wings close the corner bays' ends
    w.box(s, b, 0, -outer, b + depth, building, outer, plaster);
    w.box(s, -t / 2 - eave, top, -reach, b, top + 0.3f, reach, roof);
    // The arcade: columns between the bays (corner piers at the garth's corners),
    // parapets between the columns (a gap in the middle bay of the wing to enter the
    // garth), arches, and the wall over them up to the roof.
    const float pier = std::max(1.4f * r, t / 2);
    for (float sgn : {-1.0f, 1.0f})
      if (k % 2 == 0) w.box(s, -t / 2, 0, sgn * span - pier, t / 2, top, sgn * span + pier, stone);
    for (int i = 1; i < bays; ++i) add_column(s, w.at(0, parapet, -span + b * float(i)), r, hc, stone, st);
    for (int i = 0; i < bays; ++i) {
      const float vc = -span + b * (float(i) + 0.5f);
      if (parapet > 0 && i != bays / 2)
        w.box(s, -t / 2 + 0.05f, 0, vc - b / 2, t / 2 - 0.05f, parapet, vc + b / 2, stone);
      add_arch_piece(s, w.at(-t / 2, spring, vc), wing_v(w), {0, 1, 0}, wing_u(w) * t, b, rise, arch_r, st.segments(16),
                     stone, st);
    }
    w.box(s, -t / 2, arch_top, -span, t / 2, top, span, stone);
    // Overhead: a groin vault per bay, or a flat ceiling on beams across the walk.
    const int cells = k % 2 ? bays : bays + 2;
    for (int i = 0; i < cells; ++i) {
      const float vc = -reach + b * (float(i) + 0.5f);
      if (groin) {
        add_groin_vault(s, w.at(b / 2, ceiling, vc), b / 2, st.smooth ? 16 : 8, stone, st.smooth);
      } else {
        w.box(s, 0, ceiling - 0.22f, vc - b / 2 - 0.1f, b, ceiling, vc - b / 2 + 0.1f, wood);  // a beam
        if (i + 1 == cells) w.box(s, 0, ceiling - 0.22f, vc + b / 2 - 0.1f, b, ceiling, vc + b / 2 + 0.1f, wood);
      }
    }
    if (!groin) w.box(s, 0, ceiling, -reach, b, top + 0.01f, reach, wood);  // the boarded ceiling
    // Doors in the back wall.
    for (int i = 0; i < bays; ++i)
      if (rng.below(3) == 0)
        add_door(s, w, b, -span + b * (float(i) + 0.5f), float(rng.uniform(0.9, 1.4)), float(rng.uniform(2.1, 2.6)),
                 stone, wood);
  }
  add_garth(s, rng, X, Z, t, {stone, paving, wood}, st);
  outdoor_lighting(s, rng, 20, 65);
  if (rng.below(3) == 0) {  // a lantern hanging in one of the walks, now and then
    const int k = int(rng.below(4));
    s.points.push_back({Wing{k, k % 2 ? Z : X}.at(b / 2, ceiling - 0.8f, 0), Vec3(2.5f, 2.1f, 1.5f)});
  }
  // Cameras: in one walk, between the arcade's columns and the back wall.
  const int k = int(rng.below(4));
  const Wing w{k, k % 2 ? Z : X};
  const float span = k % 2 ? X : Z;
  const Vec3 a = w.at(t / 2 + 0.4f, 1.0f, -span + 0.4f);
  const Vec3 c = w.at(b - 0.45f, std::min(2.2f, ceiling - 0.6f), span - 0.4f);
  s.cameras = {vmin(a, c), vmax(a, c), -25, 35};
  return s;
}

namespace {

// Over a basilica's nave (half-width N, half-length L, walls H high and t thick, bays
// b long): a barrel vault springing from the clerestory's top, or a flat ceiling on
// beams; a roof slab over everything at end_top.
struct NaveSize {
  float N, L, H, t, b, end_top;
};
struct NaveMaterials {
  uint32_t stone, wood, roof;
};
void add_nave_cover(Scene& s, NaveSize n, int bays, bool vault, NaveMaterials m, const SceneStyle& st) {
  const float N = n.N, L = n.L, H = n.H, t = n.t, b = n.b, end_top = n.end_top;
  const uint32_t stone = m.stone, wood = m.wood, roof = m.roof;
  if (vault) {
    add_barrel_vault(s, {0, H, -L - 0.5f}, {0, 0, 1}, 2 * L + 1, N - t / 2, 0.25f, st.segments(32), stone, st);
  } else {
    add_box(s, {-N, H, -L - 0.5f}, {N, H + 0.3f, L + 0.5f}, wood);
    for (int i = 0; i <= bays; ++i)
      add_box(s, {-N, H - 0.35f, -L + b * float(i) - 0.15f}, {N, H, -L + b * float(i) + 0.15f}, wood);
  }
  add_box(s, {-N - t, end_top, -L - 0.5f}, {N + t, end_top + 0.3f, L + 0.5f}, roof);
}

// Pews in two blocks either side of the nave's middle passage (3 basilicas in 4).
void add_pews(Scene& s, Rng& rng, float N, float L, float b, uint32_t wood) {
  const float pew_start = -L + b * 1.2f, pew_end = L - 1.5f;
  if (rng.below(4) != 0 && pew_end - pew_start > 2)
    for (float z = pew_start; z < pew_end; z += 1.0f)
      for (float sx : {-1.0f, 1.0f}) {
        const float x0 = sx * 0.9f, x1 = sx * (N - 0.6f);
        add_box(s, {std::min(x0, x1), 0.1f, z}, {std::max(x0, x1), 0.5f, z + 0.4f}, wood);
        add_box(s, {std::min(x0, x1), 0.1f, z + 0.4f}, {std::max(x0, x1), 1.0f, z + 0.47f}, wood);
      }
}

}  // namespace

// A basilica: a nave between two arcades of columns or piers, side aisles behind them
// under galleries that open onto the nave through their own arcade of paired arches,
// a clerestory of windows over the galleries, aisle windows, a flat ceiling on beams
// or a barrel vault over the nave; pews, an altar block, sometimes hanging lamps.
// Sunlight and skylight enter through the windows, mostly far above and beside the
// view; the aisles and galleries live on bounce light.
Scene make_basilica(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  const uint32_t stone = s.add_material(random_material(rng, 0.45f, 0.85f));
  const uint32_t wall = s.add_material(random_material(rng, 0.45f, 0.85f));
  const uint32_t floor = s.add_material(random_material(rng, 0.25f, 0.6f));
  const uint32_t wood = s.add_material(random_material(rng, 0.1f, 0.4f));
  const uint32_t roof = s.add_material(random_material(rng, 0.2f, 0.5f));
  add_quad(s, {-80, 0, -80}, {160, 0, 0}, {0, 0, 160}, s.add_material(random_material(rng, 0.2f, 0.5f)));
  const float N = float(rng.uniform(3.0, 5.5));  // nave half-width, to the arcades' centre lines
  const float A = float(rng.uniform(2.6, 4.2));  // aisle width, arcade line to the outer wall's face
  const float b = float(rng.uniform(3.0, 4.4));  // bay
  const int bays = 5 + int(rng.below(4));
  const float L = b * float(bays) / 2;           // half-length
  const float t = float(rng.uniform(0.5, 0.8));  // arcade wall thickness
  const bool columns = rng.below(3) != 0;
  const float r = float(rng.uniform(0.22, 0.34));
  const float hc = float(rng.uniform(3.2, 5.0)) * st.scale;
  const float arch_r = b / 2 - 1.4f * r, rise = arch_r + float(rng.uniform(0.3, 0.7));
  const float gallery = hc + rise + 0.3f;         // gallery floor (the aisles' ceiling)
  const float hg = float(rng.uniform(2.4, 3.4));  // gallery arcade: piers' height
  const float g_r = b / 4 - 0.22f, g_rise = g_r + 0.25f;
  const float clerestory = gallery + hg + g_rise + float(rng.uniform(0.4, 1.0));  // gallery roof / clerestory sill
  const float H = clerestory + float(rng.uniform(2.5, 4.0));                      // nave wall top
  const bool vault = rng.below(2) != 0;
  const float O = N + A;  // the outer walls' inner faces at x = +-O
  // Floor, outer walls with a window per bay (some bays), the end walls with a door
  // (west, z = +L) and a high window (east), the gallery's outer wall and roof.
  add_box(s, {-O - 0.5f, 0, -L - 0.5f}, {O + 0.5f, 0.1f, L + 0.5f}, floor);
  for (float sx : {-1.0f, 1.0f}) {
    std::vector<Opening> low, high;
    for (int i = 0; i < bays; ++i) {
      const float zc = -L + b * (float(i) + 0.5f), ww = float(rng.uniform(0.5, 0.9));
      if (rng.below(3) != 0) low.push_back({zc - ww / 2, zc + ww / 2, float(rng.uniform(1.8, 2.4)), hc + rise - 0.4f});
      if (rng.below(2) != 0) high.push_back({zc - ww / 2, zc + ww / 2, gallery + 1.0f, gallery + hg});
    }
    add_wall_band(s, false, sx * (O + 0.25f), -L - 0.5f, L + 0.5f, 0, gallery, 0.5f, low, wall);
    add_wall_band(s, false, sx * (O + 0.25f), -L - 0.5f, L + 0.5f, gallery, clerestory + 0.3f, 0.5f, high, wall);
    const float x0 = sx * (N + t / 2), x1 = sx * (O + 0.5f);
    add_box(s, {std::min(x0, x1), gallery - 0.3f, -L}, {std::max(x0, x1), gallery, L}, stone);       // gallery floor
    add_box(s, {std::min(x0, x1), clerestory, -L}, {std::max(x0, x1), clerestory + 0.3f, L}, roof);  // gallery roof
  }
  const float end_top = H + (vault ? N + 0.5f : 0.5f);
  const float dw = float(rng.uniform(0.8, 1.4)), ew = float(rng.uniform(0.8, 1.6));
  add_wall(s, true, L + 0.25f, -O - 0.5f, O + 0.5f, end_top, 0.5f, {{-dw, dw, 0.1f, 3.2f}}, wall);
  add_wall(s, true, -L - 0.25f, -O - 0.5f, O + 0.5f, end_top, 0.5f,
           {{-ew, ew, clerestory, std::min(H - 0.5f, clerestory + 3.5f)}}, wall);
  add_box(s, {-dw, 0, L + 0.5f}, {dw, 3.2f, L + 0.55f}, wood);  // the west door, shut
  // The two arcades, the gallery arcades over them, the clerestory walls with windows.
  for (float sx : {-1.0f, 1.0f}) {
    const Wing w{sx > 0 ? 0 : 2, N};  // u = 0 on the arcade line, v along the nave
    for (int i = 1; i < bays; ++i) {
      const Vec3 base = w.at(0, 0.1f, -L + b * float(i));
      if (columns) add_column(s, base, r, hc - 0.1f, stone, st);
      else
        add_bevelled_box(s, base + Vec3(0, (hc - 0.1f) / 2, 0), {1.4f * r, (hc - 0.1f) / 2, 1.4f * r}, 0.05f, 0, stone,
                         st.smooth, 2);
    }
    for (float sv : {-1.0f, 1.0f})  // responds: half-piers against the end walls
      w.box(s, -t / 2, 0, sv * L - 1.4f * r, t / 2, H, sv * L + 1.4f * r, stone);
    for (int i = 0; i < bays; ++i) {
      const float vc = -L + b * (float(i) + 0.5f);
      add_arch_piece(s, w.at(-t / 2, hc, vc), wing_v(w), {0, 1, 0}, wing_u(w) * t, b, rise, arch_r, st.segments(16),
                     stone, st);
      // The gallery: a parapet, two arches on a central colonnette and side piers.
      w.box(s, -t / 2, gallery - 0.3f, vc - b / 2, t / 2, gallery + 0.9f, vc + b / 2, stone);
      w.box(s, -t / 2, gallery, vc - b / 2 - 0.22f, t / 2, gallery + hg, vc - b / 2 + 0.22f, stone);
      add_round_cylinder(s, w.at(0, gallery + 0.9f, vc), w.at(0, gallery + hg, vc), 0.1f, st.segments(12), stone,
                         st.smooth);
      w.box(s, -t / 2, gallery + hg - 0.15f, vc - 0.22f, t / 2, gallery + hg, vc + 0.22f, stone);  // its capital
      for (float sv : {-1.0f, 1.0f})
        add_arch_piece(s, w.at(-t / 2, gallery + hg, vc + sv * b / 4), wing_v(w), {0, 1, 0}, wing_u(w) * t, b / 2,
                       g_rise, g_r, st.segments(12), stone, st);
    }
    w.box(s, -t / 2, hc + rise, -L, t / 2, gallery - 0.3f, L, stone);
    w.box(s, -t / 2, gallery + hg + g_rise, -L, t / 2, clerestory + 0.3f, L, stone);
    std::vector<Opening> windows;
    for (int i = 0; i < bays; ++i) {
      const float zc = -L + b * (float(i) + 0.5f), ww = float(rng.uniform(0.6, 1.1));
      windows.push_back({zc - ww / 2, zc + ww / 2, clerestory + 0.6f, H - 0.5f});
    }
    add_wall_band(s, false, sx * N, -L - 0.5f, L + 0.5f, clerestory + 0.3f, H, t, windows, wall);
  }
  add_nave_cover(s, {N, L, H, t, b, end_top}, bays, vault, {stone, wood, roof}, st);
  add_pews(s, rng, N, L, b, wood);
  add_box(s, {-1.0f, 0.1f, -L + 0.8f}, {1.0f, 1.1f, -L + 1.8f}, stone);  // the altar block, east end
  outdoor_lighting(s, rng, 20, 60);
  if (rng.below(2))  // hanging lamps down the nave
    for (int i = 0; i < bays; i += 2) s.points.push_back({{0, hc, -L + b * (float(i) + 0.5f)}, Vec3(3.0f, 2.6f, 2.0f)});
  // Cameras on the floor of the nave and aisles, looking anywhere, often up.
  s.cameras = {{-O + 0.5f, 1.1f, -L + 2.2f}, {O - 0.5f, 2.2f, L - 0.6f}, -20, 45};
  return s;
}

}  // namespace nns::render
