#pragma once
// Procedural scene families, each aimed at something screen-space shading gets wrong
// (docs/renderer.md lists them). A scene is fully determined by (family, instance,
// seed), so a dataset can be re-rendered bit for bit, and train/test splits can use
// different instances of every family without ever sharing a scene.
#include <cstdint>
#include <string>
#include <vector>

#include "render/scene.h"

namespace nns::data {

struct SceneFamily {
  std::string name;
  std::string what_it_tests;
  Scene (*make)(uint64_t seed);
};

// All families, in a fixed order.
const std::vector<SceneFamily>& scene_families();
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

}  // namespace nns::data
