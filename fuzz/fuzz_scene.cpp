// libFuzzer target: mesh scenes for render-dataset (render/scenes/mesh_loader.cpp):
// the first byte picks OBJ, glTF (JSON) or GLB, the rest is the file.
#include <filesystem>

#include "render/scenes/mesh_loader.h"
#include "fuzz/fuzz_support.h"

using namespace nns;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const std::string dir = [] {
    std::string d = fuzz::scratch_path("scene");
    std::filesystem::create_directories(d);
    return d;
  }();
  static const char* ext[3] = {".obj", ".gltf", ".glb"};
  const std::string path = dir + "/s" + ext[data[0] % 3];
  fuzz::write_bytes(path, data + 1, size - 1);
  try {
    render::Scene s = render::load_mesh_scene(path);
    for (auto& t : s.triangles)
      for (uint32_t v : t.v)
        if (v >= s.positions.size()) fuzz::finding("a triangle refers past the vertices");
  } catch (const std::exception& e) {
    fuzz::expect_named(e, path);
  }
  return 0;
}
