#pragma once
// One camera view of a G-buffer dataset (docs/dataset-format.md): named float planes
// of width x height, plus the header attributes. Channel names follow the spec
// exactly ("Z", "N.X", "AO", "albedo.R", ...). Planes are row-major, row 0 at the top.
#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace nns::data {

struct View {
  int width = 0, height = 0;
  float fov_y_deg = 0;             // `fovY`, required
  std::optional<float> ao_radius;  // `aoRadius`, required when AO is present
  std::string scene;               // `scene`, required
  // row-major 4x4 for column vectors (p_cam = M * p_world, translation in [3],[7],[11]);
  // the EXR attribute stores its transpose (Imath multiplies row vectors). Optional.
  std::optional<std::array<float, 16>> world_to_camera;
  std::map<std::string, std::vector<float>> channels;
  std::string source;  // file it was read from (for error messages)

  bool has(const std::string& name) const { return channels.count(name) != 0; }

  const std::vector<float>& channel(const std::string& name) const {
    auto it = channels.find(name);
    if (it == channels.end())
      throw std::runtime_error((source.empty() ? std::string("view") : source) + ": missing channel '" + name + "'");
    return it->second;
  }
  // Creates the plane (zero-filled) if absent.
  std::vector<float>& add_channel(const std::string& name) {
    auto& c = channels[name];
    c.assign(size_t(width) * size_t(height), 0.0f);
    return c;
  }
  float at(const std::string& name, int x, int y) const { return channel(name)[size_t(y) * size_t(width) + size_t(x)]; }
};

// Depth at or beyond this (or inf) is sky: no geometry.
inline constexpr float kSkyDepth = 1e30f;
inline bool is_sky(float z) { return !(z < kSkyDepth) || z <= 0; }

// The depth the format allows: > 0, sky as +inf or >= 1e30. NaN, 0, negative and -inf
// are defects (is_sky() alone would take them for sky): throws "<file>: channel 'Z':
// ..." naming the first such pixel and how many there are.
inline void check_depth(const View& v) {
  if (!v.has("Z")) return;
  const auto& z = v.channel("Z");
  size_t first = 0, bad = 0;
  for (size_t i = 0; i < z.size(); ++i)
    if (!(z[i] > 0)) {
      if (bad++ == 0) first = i;
    }
  if (!bad) return;
  const size_t w = size_t(std::max(v.width, 1));
  throw std::runtime_error((v.source.empty() ? std::string("view") : v.source) + ": channel 'Z': invalid depth " +
                           std::to_string(z[first]) + " at x=" + std::to_string(first % w) +
                           ", y=" + std::to_string(first / w) + " (" + std::to_string(bad) +
                           (bad == 1 ? " pixel" : " pixels") + "); depth must be > 0, sky is +inf or >= 1e30");
}

}  // namespace nns::data
