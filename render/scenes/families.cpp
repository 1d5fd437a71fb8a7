#include "render/scenes/families.h"

#include <stdexcept>

namespace nns::render {

const std::vector<SceneFamily>& scene_families() {
  static const std::vector<SceneFamily> all = {
      {"room", "furniture, clutter, corners and nooks lit by lamps and bounces", make_room},
      {"window-room", "sunlight through windows falling behind the camera", make_window_room},
      {"colonnade", "pillars, arches, lintels and shaded halls", make_colonnade},
      {"stairs", "steps and railings: repeated creases, thin posts", make_stairs},
      {"voxel", "Minecraft-like block terrain, houses and trees", make_voxel},
      {"thin", "poles, fences, wires and leaf slabs thinner than a depth step", make_thin},
      {"floating", "objects floating in front of far walls: large depth discontinuities", make_floating},
      {"offscreen", "overhangs and walls just outside the screen", make_offscreen},
      {"lounge", "sofas, round tables, chairs on thin legs, bookshelves, lamps: upholstered and turned furniture",
       make_lounge, 2},
      {"clutter", "rooms piled with generated meshes of every size: rounded boxes, blobs, rings, cones, unions",
       make_clutter, 2},
      {"stairwell", "spiral and switchback stairs in a shaft: treads, soffits, posts and helical rails", make_stairwell,
       2},
      {"arcade", "round columns, arches and a barrel-vaulted walkway: curved creases", make_arcade, 2},
      {"vaults", "groin and barrel vaults on piers: concave ceilings meeting in groins", make_vaults, 2},
      {"foliage", "trees, shrubs and grass: thousands of thin overlapping leaves and branches", make_foliage, 2},
      {"terrain", "displaced height field with ridges and half-buried rocks, seen from above", make_terrain, 2},
      {"cave", "inside a displaced rock shell: concave walls, stalagmites, boulders", make_cave, 2},
      {"round", "spheres, tori, capsules, cones, domes and bowls resting on the ground", make_round, 2},
      {"pipes", "pipe runs, tanks with domed ends, valve wheels, a grating walkway", make_pipes, 2},
      {"street", "a street canyon: recessed windows, balconies, parked cars, lamp posts", make_street, 2},
      {"corridor",
       "long corridors: side rooms through doors, niches, beams, a turn or T-junction lit from outside round the "
       "corner",
       make_corridor, 3},
      {"courtyard",
       "an open-sky court enclosed by wings with arcades, eaves and balconies: buildings occlude sky and sun",
       make_courtyard, 3},
      {"multiroom", "3-6 rooms joined by doorways, furnished, lamps in some rooms only: light arrives through doors",
       make_multiroom, 3},
      {"cloister",
       "covered walks round a sunlit garth: arcades on columns, groin vaults, light entering sideways from out of view",
       make_cloister, 4},
      {"basilica",
       "a nave between arcades, galleries over the aisles, clerestory windows: light from high openings out of view",
       make_basilica, 4},
  };
  return all;
}

std::vector<std::string> scene_family_names(int generation) {
  std::vector<std::string> names;
  for (auto& f : scene_families())
    if (f.generation == generation) names.push_back(f.name);
  return names;
}

const SceneFamily& scene_family(const std::string& name) {
  std::string known;
  for (auto& f : scene_families()) {
    if (f.name == name) return f;
    known += (known.empty() ? "" : ", ") + f.name;
  }
  throw std::invalid_argument("unknown scene family '" + name + "' (known: " + known + ")");
}

Scene make_family_scene(const std::string& family, int instance, uint64_t seed) {
  const SceneFamily& f = scene_family(family);
  // Mix (seed, family, instance) so neighbouring instances share no random stream.
  uint64_t h = seed * 0x9E3779B97F4A7C15ull + uint64_t(instance) * 0xBF58476D1CE4E5B9ull;
  for (char c : family) h = (h ^ uint64_t(uint8_t(c))) * 0x100000001B3ull;
  Scene s = f.make(h);
  if (!s.normals.empty()) s.normals.resize(s.positions.size());  // flat parts added after the last smooth one
  s.name = family + "-" + std::to_string(instance);
  return s;
}

}  // namespace nns::render
