#pragma once
// The camera that tools/blender_capture.py writes into each Blender EXR, so that
// import-blender needs no hand-copied numbers. Blender keeps no custom EXR attributes, but
// it writes the render stamp "Note" (Output > Metadata > Note) as the header string
// attribute `Note`; the script fills it with (docs/blender.md, "The capture note"):
//
//   nnshade-camera 1
//   fovY=26.9914676
//   worldToCamera=1,0,0,0, 0,0.12,0.99,-0.88, 0,-0.99,0.12,-5.1, 0,0,0,1   (row by row)
//   aoRadius=1
//   scene=room
//   camera=CamA
//
// The header is outside bytes: a note that starts with the magic line but is malformed
// is an error naming the file; any other note is the user's own text and is ignored.
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

namespace nns::data::blender {

inline constexpr const char* kCaptureNoteMagic = "nnshade-camera 1";

// One finite number filling all of `text` (strtof alone accepts "1x", "nan", "inf").
inline std::optional<float> parse_finite(const std::string& text) {
  const char* begin = text.c_str();
  while (*begin == ' ') ++begin;
  char* end = nullptr;
  errno = 0;
  float v = std::strtof(begin, &end);
  if (end == begin || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
  while (*end == ' ') ++end;
  if (*end != '\0') return std::nullopt;
  return v;
}

// 16 comma-separated finite numbers, row by row; `what` starts the error message.
inline std::array<float, 16> parse_matrix(const std::string& s, const std::string& what = "--world-to-camera") {
  std::array<float, 16> m{};
  size_t n = 0, start = 0;
  while (start <= s.size()) {
    size_t comma = s.find(',', start);
    if (comma == std::string::npos) comma = s.size();
    auto v = parse_finite(s.substr(start, comma - start));
    if (n == 16 || !v) throw std::runtime_error(what + ": expected 16 comma-separated finite numbers, row by row");
    m[n++] = *v;
    start = comma + 1;
  }
  if (n != 16) throw std::runtime_error(what + ": expected 16 comma-separated finite numbers, row by row");
  return m;
}

struct CaptureNote {
  float fov_y = 0, ao_radius = 0;
  std::array<float, 16> world_to_camera{};
  std::string scene, camera;  // scene may be empty (then the file name is used)
};

// nullopt when `note` is not a capture note; throws "<file>: Note: <problem>" when it
// claims to be one and is not well formed.
inline std::optional<CaptureNote> parse_capture_note(const std::string& note, const std::string& file) {
  const std::string magic = kCaptureNoteMagic;
  const size_t first_end = std::min(note.find('\n'), note.size());
  const std::string first = note.substr(0, first_end);
  if (first.rfind("nnshade-camera", 0) != 0) return std::nullopt;
  auto fail = [&](const std::string& what) -> std::runtime_error {
    return std::runtime_error(file + ": Note (written by tools/blender_capture.py): " + what);
  };
  if (first != magic) throw fail("first line '" + first.substr(0, 40) + "' is not '" + magic + "' (another version?)");
  CaptureNote c;
  bool fov = false, matrix = false, radius = false, scene = false, camera = false;
  size_t pos = first_end + 1;
  while (pos < note.size()) {
    size_t end = std::min(note.find('\n', pos), note.size());
    const std::string line = note.substr(pos, end - pos);
    pos = end + 1;
    if (line.empty()) continue;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) throw fail("line without '=': '" + line.substr(0, 40) + "'");
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    auto once = [&](bool& seen) {
      if (seen) throw fail("'" + key + "' given twice");
      seen = true;
    };
    if (key == "fovY") {
      once(fov);
      auto v = parse_finite(value);
      if (!v || !(*v > 0 && *v < 180)) throw fail("fovY must be degrees in (0, 180)");
      c.fov_y = *v;
    } else if (key == "aoRadius") {
      once(radius);
      auto v = parse_finite(value);
      if (!v || !(*v > 0)) throw fail("aoRadius must be a positive number");
      c.ao_radius = *v;
    } else if (key == "worldToCamera") {
      once(matrix);
      try {
        c.world_to_camera = parse_matrix(value, "worldToCamera");
      } catch (const std::runtime_error& e) {
        throw fail(e.what());
      }
    } else if (key == "scene") {
      once(scene);
      c.scene = value;
    } else if (key == "camera") {
      once(camera);
      c.camera = value;
    }  // other keys: a later version's additions, ignored
  }
  if (!fov || !matrix || !radius) throw fail("needs fovY, worldToCamera and aoRadius");
  return c;
}

}  // namespace nns::data::blender
