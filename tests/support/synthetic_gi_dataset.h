#pragma once
// A tiny synthetic surround GI dataset for the app tests (train-gan, eval-gi, gi-infer):
// smooth light that varies with face, position and frame, so there is something to
// learn; only the front face carries the indirect.* target, as the contract allows.
//   write_dataset(root, 3, 2);   // root/train/frame0..2, root/test/frame0..1, 16x16 faces
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/rng.h"
#include "data/exr_io.h"
#include "data/view.h"

namespace nns::testing {

using nns::data::View;

// A face of a smooth synthetic scene: light varies with the face and position so there
// is something to learn, and each frame differs.
inline View make_face(int F, int frame, int face, bool targets, uint64_t seed) {
  View v;
  v.width = v.height = F;
  v.fov_y_deg = 90;
  v.scene = "synthetic" + std::to_string(frame % 2);
  nns::Rng rng(seed * 977 + uint64_t(frame * 6 + face));
  const char* ch[] = {"Z",        "N.X",      "N.Y",   "N.Z",   "albedo.R", "albedo.G",   "albedo.B",   "direct.R",
                      "direct.G", "direct.B", "env.R", "env.G", "env.B",    "indirect.R", "indirect.G", "indirect.B"};
  for (const char* c : ch) {
    std::string name = c;
    if (!targets && name.rfind("indirect", 0) == 0) continue;
    auto& p = v.add_channel(name);
    for (int y = 0; y < F; ++y)
      for (int x = 0; x < F; ++x) {
        float u = float(x) / F, w = float(y) / F;
        float val = 0.5f + 0.3f * std::sin(3 * u + frame + face) * std::cos(2 * w - face);
        if (name == "Z") val = (y < F / 4 && face == 4) ? INFINITY : 1 + 4 * w + frame * 0.1f;
        else if (name == "N.X") val = 0.3f * std::sin(u * 4);
        else if (name == "N.Y") val = 0.2f;
        else if (name == "N.Z") val = std::sqrt(1 - 0.04f - 0.09f * std::sin(u * 4) * std::sin(u * 4));
        else if (name.rfind("direct", 0) == 0) val = (x > F / 2 + face ? 2.0f : 0.0f) * (1 + 0.1f * frame);
        else if (name.rfind("indirect", 0) == 0) val *= 0.5f;
        else if (name.rfind("env", 0) == 0) val *= 0.2f;
        // Normals stay unit length (the dataset contract; trainers validate it first).
        const float noise = 0.01f * float(rng.uniform());
        p[size_t(y * F + x)] = name.rfind("N.", 0) == 0 ? val : val + noise;
      }
  }
  return v;
}

inline void write_dataset(const std::string& root, int train_frames, int test_frames, bool drop_left = false,
                          int face_size = 16) {
  const char* faces[] = {"front", "back", "left", "right", "up", "down"};
  for (int split = 0; split < 2; ++split) {
    int n = split == 0 ? train_frames : test_frames;
    for (int f = 0; f < n; ++f) {
      std::string dir = root + (split == 0 ? "/train/" : "/test/") + "frame" + std::to_string(f);
      std::filesystem::create_directories(dir);
      for (int k = 0; k < 6; ++k) {
        if (drop_left && split == 1 && f == 0 && k == 2) continue;
        View v = make_face(face_size, f + 100 * split, k, k == 0, 7);
        if (split == 1) v.scene = "held-out";
        nns::data::write_view(dir + "/" + faces[k] + ".exr", v);
      }
    }
  }
}

}  // namespace nns::testing
