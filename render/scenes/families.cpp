#include "render/scenes/families.h"

#include <stdexcept>

namespace nns::data {

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
  };
  return all;
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
  s.name = family + "-" + std::to_string(instance);
  return s;
}

}  // namespace nns::data
