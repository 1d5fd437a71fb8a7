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
//  - AO (RGB, grey) -> AO, with --ao-radius set to the world's AO distance
//    (world.light_settings.distance).
//  - The camera (fovY, worldToCamera, aoRadius, scene) comes from the capture note that
//    tools/blender_capture.py writes into the header (data/blender_capture_note.h);
//    flags given by hand override it (with_capture_note()).
//  - Env is Blender's directly visible background, not sky light on surfaces (Cycles
//    counts that in DiffDir); it is imported as env only with --keep-env.
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/blender_capture_note.h"
#include "data/exr_io.h"
#include "data/view.h"

namespace nns::data {

namespace blender {

struct ImportSettings {
  float fov_y = 0;  // 0: from the file's capture note
  std::optional<float> ao_radius;
  std::string scene, layer;
  std::optional<std::array<float, 16>> world_to_camera;
  bool keep_env = false, half = false;
  float sky_depth = 1e9f;
};

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
    throw std::runtime_error(in.source + ": no channel '" + wanted +
                             ".Depth.Z' (enable the Z pass in that view layer)");
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

// The settings for one file: the flags, with what they leave unset taken from the file's
// capture note. A flag that disagrees with the note wins; `overrides` gets a line saying so.
inline ImportSettings with_capture_note(const ImportSettings& flags, const std::optional<CaptureNote>& note,
                                        std::vector<std::string>* overrides = nullptr) {
  ImportSettings s = flags;
  if (!note) return s;
  auto differs = [&](const std::string& what, bool d) {
    if (d && overrides) overrides->push_back(what + " given by hand overrides the file's capture note");
  };
  differs("--fov-y", s.fov_y > 0 && std::abs(s.fov_y - note->fov_y) > 1e-4f * note->fov_y);
  if (!(s.fov_y > 0)) s.fov_y = note->fov_y;
  differs("--ao-radius", s.ao_radius && std::abs(*s.ao_radius - note->ao_radius) > 1e-6f * note->ao_radius);
  if (!s.ao_radius) s.ao_radius = note->ao_radius;
  differs("--world-to-camera", s.world_to_camera && *s.world_to_camera != note->world_to_camera);
  if (!s.world_to_camera) s.world_to_camera = note->world_to_camera;
  differs("--scene", !s.scene.empty() && !note->scene.empty() && s.scene != note->scene);
  if (s.scene.empty()) s.scene = note->scene;
  return s;
}

inline void require_fov(const ImportSettings& s, const std::string& file) {
  if (!(s.fov_y > 0 && s.fov_y < 180))
    throw std::runtime_error(file +
                             ": no field of view: render with tools/blender_capture.py (it writes the "
                             "camera into the file) or give --fov-y (docs/blender.md)");
}

inline View convert(const View& in, const ImportSettings& s) {
  require_fov(s, in.source);
  const std::string layer = find_layer(in, s.layer);
  auto pass = [&](const std::string& p) { return layer.empty() ? p : layer + "." + p; };
  View out;
  out.width = in.width;
  out.height = in.height;
  out.fov_y_deg = s.fov_y;
  out.scene = s.scene.empty() ? std::filesystem::path(in.source).stem().string() : s.scene;
  out.world_to_camera = s.world_to_camera ? s.world_to_camera : in.world_to_camera;
  const size_t n = size_t(in.width) * size_t(in.height);

  // "<file>: pass <name>, pixel (x, y): <problem>": what a user needs to find it.
  auto at = [&](const std::string& p, size_t i, const std::string& what) {
    return std::runtime_error(in.source + ": pass " + p + ", pixel (" + std::to_string(i % size_t(in.width)) + ", " +
                              std::to_string(i / size_t(in.width)) + "): " + what);
  };
  auto& z = out.add_channel("Z");
  z = in.channel(pass("Depth.Z"));
  // Cycles writes the background as 0 or a huge value (sky); a NaN or a negative depth is
  // no distance at all, and made sky it would hide a broken render.
  for (size_t i = 0; i < z.size(); ++i) {
    float& v = z[i];
    if (std::isnan(v) || v < 0)
      throw at(pass("Depth.Z"), i, "depth " + std::to_string(v) + " is no distance (NaN or negative)");
    if (v == 0 || v >= s.sky_depth) v = INFINITY;
  }

  if (in.has(pass("Normal.X"))) {
    if (!out.world_to_camera)
      throw std::runtime_error(in.source +
                               ": world-space normals need the camera: render with "
                               "tools/blender_capture.py, or pass --world-to-camera (docs/blender.md)");
    const auto& m = *out.world_to_camera;
    // The rotation part must turn a direction into one: 16 zeros made every normal zero.
    const double det = double(m[0]) * (double(m[5]) * m[10] - double(m[6]) * m[9]) -
                       double(m[1]) * (double(m[4]) * m[10] - double(m[6]) * m[8]) +
                       double(m[2]) * (double(m[4]) * m[9] - double(m[5]) * m[8]);
    if (!(std::fabs(det) > 1e-12) || !std::isfinite(det))
      throw std::runtime_error(in.source + ": the world-to-camera matrix's upper-left 3x3 is singular (determinant " +
                               std::to_string(det) + "): it rotates no normal into camera space");
    const auto &wx = in.channel(pass("Normal.X")), &wy = in.channel(pass("Normal.Y")),
               &wz = in.channel(pass("Normal.Z"));
    auto &nx = out.add_channel("N.X"), &ny = out.add_channel("N.Y"), &nz = out.add_channel("N.Z");
    for (size_t i = 0; i < n; ++i) {
      if (is_sky(z[i])) continue;  // zero on sky, as the spec allows
      // Directions take the upper-left 3x3 (no translation); renormalise against scale.
      // In double: a tiny normal's squares are subnormal in float, and its length then
      // lost the digits that make the result unit (a fuzzer found 1e-20-sized normals).
      double c[3];
      for (int r = 0; r < 3; ++r)
        c[r] = double(m[size_t(4 * r)]) * wx[i] + double(m[size_t(4 * r + 1)]) * wy[i] +
               double(m[size_t(4 * r + 2)]) * wz[i];
      const double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      if (!(len > 0 && std::isfinite(len))) {
        const char* axis = !std::isfinite(wx[i])   ? "Normal.X"
                           : !std::isfinite(wy[i]) ? "Normal.Y"
                           : !std::isfinite(wz[i]) ? "Normal.Z"
                                                   : "Normal.X";
        throw at(pass(axis), i,
                 "the normal (" + std::to_string(wx[i]) + ", " + std::to_string(wy[i]) + ", " + std::to_string(wz[i]) +
                     ") has no direction (NaN, infinite or zero)");
      }
      nx[i] = float(c[0] / len), ny[i] = float(c[1] / len), nz[i] = float(c[2] / len);
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
        throw std::runtime_error(in.source +
                                 ": has an AO pass; give its distance with --ao-radius (Blender 3.x: "
                                 "Render Properties > Light Paths > Fast GI Approximation > AO Distance, "
                                 "world.light_settings.distance, default 10), or render with tools/blender_capture.py");
      out.add_channel("AO") = in.channel(pass(ao));
      out.ao_radius = s.ao_radius;
      break;
    }
  return out;
}

}  // namespace blender

}  // namespace nns::data
