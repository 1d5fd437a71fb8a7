#pragma once
// Procedural scene families, each aimed at something screen-space shading gets wrong
// (docs/renderer.md lists them). A scene is fully determined by (family, instance,
// seed), so a dataset can be re-rendered bit for bit, and train/test splits can use
// different instances of every family without ever sharing a scene.
#include <cstdint>
#include <string>
#include <vector>

#include "render/scene.h"

namespace nns::render {

struct SceneFamily {
  std::string name;
  std::string what_it_tests;
  Scene (*make)(uint64_t seed);
  // 1: the original eight, the default of the nnao/gi/surround presets (whose output
  // must not change); 2: the families built on mesh_builder.h (curved surfaces,
  // generated meshes), added for the nnao-v2 preset; 3: buildings of several spaces
  // (corridors, courtyards, multi-room floors) for light from out of view, added for
  // the surround-v3 preset (nnao-v2 and surround-v2 keep generations 1 and 2); 4:
  // monumental halls lit through openings out of view (cloister, basilica), added for
  // the surround-v4 preset.
  int generation = 1;
};

// All families, in a fixed order: generation 1, then 2, then 3, then 4.
const std::vector<SceneFamily>& scene_families();
// The names of the families of one generation, in that order.
std::vector<std::string> scene_family_names(int generation);
// Throws naming the unknown family and listing the known ones.
const SceneFamily& scene_family(const std::string& name);
// Instance `instance` of `family` under dataset seed `seed`; named "<family>-<instance>".
Scene make_family_scene(const std::string& family, int instance, uint64_t seed);

// The individual generators (families_*.cpp).
Scene make_room(uint64_t seed);
Scene make_window_room(uint64_t seed);
Scene make_colonnade(uint64_t seed);
Scene make_stairs(uint64_t seed);
Scene make_voxel(uint64_t seed);
Scene make_thin(uint64_t seed);
Scene make_floating(uint64_t seed);
Scene make_offscreen(uint64_t seed);
// Generation 2 (families_interior/architecture/nature/shapes.cpp).
Scene make_lounge(uint64_t seed);
Scene make_clutter(uint64_t seed);
Scene make_stairwell(uint64_t seed);
Scene make_arcade(uint64_t seed);
Scene make_vaults(uint64_t seed);
Scene make_street(uint64_t seed);
Scene make_foliage(uint64_t seed);
Scene make_terrain(uint64_t seed);
Scene make_cave(uint64_t seed);
Scene make_round(uint64_t seed);
Scene make_pipes(uint64_t seed);
// Generation 3 (families_plans.cpp, families_courtyard.cpp).
Scene make_corridor(uint64_t seed);
Scene make_courtyard(uint64_t seed);
Scene make_multiroom(uint64_t seed);
// Generation 4 (families_halls.cpp).
Scene make_cloister(uint64_t seed);
Scene make_basilica(uint64_t seed);

}  // namespace nns::render
