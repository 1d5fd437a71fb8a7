#pragma once
// Converting Blender multilayer EXR renders (Cycles passes, names such as
// "ViewLayer.Depth.Z", "ViewLayer.Normal.X") into the dataset format
// (docs/dataset-format.md); the recipe is docs/blender.md.
//
// What changes on the way:
//  - Normal: Cycles writes world-space normals; they are rotated into camera space with
//    the world-to-camera matrix (--world-to-camera, or the file's worldToCamera
//    attribute). Blender's camera looks down its local -Z with +Y up, which is already
//    OpenGL's camera space, so no axis swap is needed.
//  - Depth: Cycles' Z pass is planar for perspective cameras (camera_z_depth(): the z of
//    the point in camera space), as the spec wants; the background holds 0 or a huge
//    value (1e10), both become +inf (sky).
//  - DiffCol -> albedo, DiffDir -> direct, DiffInd -> indirect, Emit -> emission
//    (Cycles' diffuse light passes are already "before multiplying by colour").
//  - AO (RGB, grey) -> AO, with --ao-radius set to the view layer's AO distance.
//  - Env is Blender's directly visible background, not sky light on surfaces (Cycles
//    counts that in DiffDir); it is imported as env only with --keep-env.
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/exr_io.h"
#include "data/view.h"

namespace nns::data {

namespace blender {


struct ImportSettings {
  float fov_y = 0;
  std::optional<float> ao_radius;
  std::string scene, layer;
  std::optional<std::array<float, 16>> world_to_camera;
  bool keep_env = false, half = false;
  float sky_depth = 1e9f;
};

inline std::array<float, 16> parse_matrix(const std::string& s) {
  std::array<float, 16> m{};
  std::stringstream ss(s);
  std::string item;
  int n = 0;
  while (std::getline(ss, item, ',')) {
    if (n == 16) break;
    size_t pos = 0;
    m[size_t(n++)] = std::stof(item, &pos);
  }
  if (n != 16 || std::getline(ss, item, ','))
    throw std::invalid_argument("--world-to-camera: expected 16 comma-separated numbers, row by row");
  return m;
}

// The view layer: the prefix of "<layer>.Depth.Z" ("" for single-layer files).
inline std::string find_layer(const View& in, const std::string& wanted) {
  std::vector<std::string> layers;
  for (auto& [name, plane] : in.channels) {
    const std::string suffix = "Depth.Z";
    if (name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      std::string prefix = name.substr(0, name.size() - suffix.size());
      layers.push_back(prefix.empty() ? "" : prefix.substr(0, prefix.size() - 1));
    }
  }
  if (!wanted.empty()) {
    for (auto& l : layers)
      if (l == wanted) return l;
    throw std::runtime_error(in.source + ": no channel '" + wanted + ".Depth.Z' (enable the Z pass in that view layer)");
  }
  if (layers.empty())
    throw std::runtime_error(in.source + ": no '<ViewLayer>.Depth.Z' channel; enable Passes > Data > Z in Blender");
  if (layers.size() > 1) {
    std::string all;
    for (auto& l : layers) all += (all.empty() ? "" : ", ") + l;
    throw std::runtime_error(in.source + ": several view layers (" + all + "); choose one with --layer");
  }
  return layers[0];
}

inline View convert(const View& in, const ImportSettings& s) {
  const std::string layer = find_layer(in, s.layer);
  auto pass = [&](const std::string& p) { return layer.empty() ? p : layer + "." + p; };
  View out;
  out.width = in.width;
  out.height = in.height;
  out.fov_y_deg = s.fov_y;
  out.scene = s.scene.empty() ? std::filesystem::path(in.source).stem().string() : s.scene;
  out.world_to_camera = s.world_to_camera ? s.world_to_camera : in.world_to_camera;
  const size_t n = size_t(in.width) * size_t(in.height);

  auto& z = out.add_channel("Z");
  z = in.channel(pass("Depth.Z"));
  for (float& v : z)
    if (!(v > 0) || v >= s.sky_depth) v = INFINITY;

  if (in.has(pass("Normal.X"))) {
    if (!out.world_to_camera)
      throw std::runtime_error(in.source + ": world-space normals need the camera: pass --world-to-camera "
                               "(see docs/blender.md) or write a worldToCamera attribute");
    const auto& m = *out.world_to_camera;
    const auto &wx = in.channel(pass("Normal.X")), &wy = in.channel(pass("Normal.Y")), &wz = in.channel(pass("Normal.Z"));
    auto &nx = out.add_channel("N.X"), &ny = out.add_channel("N.Y"), &nz = out.add_channel("N.Z");
    for (size_t i = 0; i < n; ++i) {
      if (is_sky(z[i])) continue;  // zero on sky, as the spec allows
      // Directions take the upper-left 3x3 (no translation); renormalise against scale.
      float c[3];
      for (int r = 0; r < 3; ++r) c[r] = m[size_t(4 * r)] * wx[i] + m[size_t(4 * r + 1)] * wy[i] + m[size_t(4 * r + 2)] * wz[i];
      float len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      if (len > 0) nx[i] = c[0] / len, ny[i] = c[1] / len, nz[i] = c[2] / len;
    }
  }

  std::vector<std::pair<std::string, std::string>> rgb = {
      {"DiffCol", "albedo"}, {"DiffDir", "direct"}, {"DiffInd", "indirect"}, {"Emit", "emission"}};
  if (s.keep_env) rgb.push_back({"Env", "env"});
  for (auto& [from, to] : rgb)
    for (const char* c : {"R", "G", "B"})
      if (in.has(pass(from + "." + c))) out.add_channel(to + "." + c) = in.channel(pass(from + "." + c));

  for (const char* ao : {"AO.R", "AO.X", "AO.V"})
    if (in.has(pass(ao))) {
      if (!s.ao_radius)
        throw std::runtime_error(in.source + ": has an AO pass; give its distance with --ao-radius "
                                 "(View Layer > Light > AO distance / World > Ambient Occlusion)");
      out.add_channel("AO") = in.channel(pass(ao));
      out.ao_radius = s.ao_radius;
      break;
    }
  return out;
}

}  // namespace blender

}  // namespace nns::data
