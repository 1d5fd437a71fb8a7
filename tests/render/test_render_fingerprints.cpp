// The presets users have cached render the same numbers, bit for bit: a fingerprint of
// every channel of every view of a small render of each preset, taken with the renderer
// before its speed settings existed (surround-v5's adaptive paths and fewer side-face
// rays, docs/renderer.md). The jobs trace every estimator (AO, direct with area lights
// and sun discs, env packets, paths with roulette and one-light NEE, textures) at a few
// samples each, with 2 threads (the pixels are the same with 1).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/thread_pool.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "render/dataset_writer.h"

using namespace nns;
using namespace nns::data;
namespace fs = std::filesystem;

namespace {
fs::path temp_root() { return fs::temp_directory_path() / ("nnshade-fingerprints-" + std::to_string(::getpid())); }

// FNV-1a over the bytes of `n` bytes at `p`.
void fnv(uint64_t& h, const void* p, size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001B3ull;
}

// Every view (or face) file of the dataset in listing order: its path below the root,
// then each channel's name and float bits (channels in name order), size and aoRadius.
uint64_t dataset_fingerprint(const std::string& root) {
  uint64_t h = 0xcbf29ce484222325ull;
  DatasetListing l = list_dataset(root);
  std::vector<std::string> files;
  for (const SplitListing* s : {&l.train, &l.test, &l.holdout}) {
    for (auto& v : s->views) files.push_back(v);
    for (auto& f : s->frames)
      for (auto& face : f.faces) files.push_back(face);
  }
  EXPECT_FALSE(files.empty()) << root;
  for (const std::string& file : files) {
    std::string rel = fs::path(file).lexically_relative(root).string();
    fnv(h, rel.data(), rel.size());
    View v = read_view(file);
    fnv(h, &v.width, sizeof v.width);
    fnv(h, &v.height, sizeof v.height);
    float radius = v.ao_radius.value_or(-1.0f);
    fnv(h, &radius, sizeof radius);
    for (auto& [name, plane] : v.channels) {
      fnv(h, name.data(), name.size());
      fnv(h, plane.data(), plane.size() * sizeof(float));
    }
  }
  return h;
}

struct Case {
  const char* preset;
  uint64_t fingerprint;  // recorded with the renderer before surround-v5's settings existed
};

DatasetJob fingerprint_job(const std::string& preset, const std::string& out) {
  DatasetJob j;
  j.preset = preset;
  j.out = out;
  j.views = 6;
  j.views_per_scene = 2;
  j.path_frames = 2;
  j.width = j.height = 12;
  j.fov_y_deg = 70;
  j.settings.ao_spp = 20, j.settings.gi_spp = 24, j.settings.light_spp = 2, j.settings.bounces = 3;
  j.settings.seed = 7;
  // Families with suns, lamps, rect lights, curved meshes and (surround-v4) textures.
  j.families = {"window-room", "corridor", "lounge", "cloister"};
  if (preset == "nnao" || preset == "gi" || preset == "surround") j.families = {"room", "window-room", "offscreen"};
  if (preset == "nnao-v2" || preset == "surround-v2") j.families = {"window-room", "lounge", "vaults"};
  if (preset == "surround-v3") j.families = {"window-room", "corridor", "lounge"};
  j.progress = false;
  return j;
}
}  // namespace

TEST(RenderFingerprints, ExistingPresetsRenderTheSameNumbers) {
#if !defined(__FMA__)
  GTEST_SKIP() << "the fingerprints were recorded in the native build (FMA contraction); a portable build "
                  "rounds differently";
#endif
  const Case cases[] = {
      {"nnao", 0x6f30cef432af4c8bull},        {"nnao-v2", 0xe4a3627b7d53e47aull},
      {"gi", 0xf8b49332416418cbull},          {"surround", 0x3fcb519a9c1652afull},
      {"surround-v2", 0xa68593e7024705a5ull}, {"surround-v3", 0xb80c36a7144d0fc5ull},
      {"surround-v4", 0xe0f5e140765b1eedull},
  };
  set_num_threads(2);
  const fs::path root = temp_root();
  fs::remove_all(root);
  for (const Case& c : cases) {
    DatasetJob job = fingerprint_job(c.preset, (root / c.preset).string());
    render_dataset(job);
    const uint64_t f = dataset_fingerprint(job.out);
    std::printf("fingerprint %-12s %016llx\n", c.preset, (unsigned long long)f);
    EXPECT_EQ(f, c.fingerprint) << c.preset << ": the numbers of an existing preset changed";
  }
  fs::remove_all(root);
}
