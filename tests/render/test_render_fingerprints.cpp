// The presets users have cached render the same numbers: every channel of every view of a
// small render of each preset is compared, value by value, with a reference recorded with
// the renderer before its speed settings existed (surround-v5's adaptive paths and fewer
// side-face rays, docs/renderer.md). The jobs trace every estimator (AO, direct with area
// lights and sun discs, env packets, paths with roulette and one-light NEE, textures) at a
// few samples each, with 2 threads (the pixels are the same with 1).
//
// The comparison is not bitwise, because the bits depend on the build: -O1 under the
// sanitizers, -O3 natively and another CPU's FMA contraction round differently, and a
// rounding that moves a ray past an edge or a roulette draw past its threshold changes that
// pixel's estimate outright. Each value is stored as one byte, a hash of the value rounded
// to 10 mantissa bits. Against references recorded with -O3 -march=native on an AVX2 Zen 2,
// the sanitizer build (-O1) and the portable build (x86-64, no FMA) change at most 1.4% of
// a channel's values (surround-v2's indirect light, where a few paths take another branch),
// while one more AO and path sample, which only moves the random streams, changes 12-57% of
// every stochastic channel's values (the rest are exact: sky, unoccluded, unlit).
// The albedo channels are among them: surround-v4's textures must not reach the presets
// before it (a texture changes most of a face's albedo values; an AVX-512 build changes
// some albedo values in their last bits only, none at 10 mantissa bits).
// NNSHADE_RECORD_RENDER_REFERENCES=1 writes the references anew.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "core/thread_pool.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "render/dataset_writer.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;
namespace fs = std::filesystem;

namespace {
fs::path temp_root() { return fs::temp_directory_path() / ("nnshade-fingerprints-" + std::to_string(::getpid())); }
fs::path reference_path(const std::string& preset) {
  return fs::path(NNSHADE_SOURCE_DIR) / "tests" / "render" / "references" / (preset + ".bin");
}

// FNV-1a over the bytes of `n` bytes at `p`.
void fnv(uint64_t& h, const void* p, size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001B3ull;
}

// One byte for a value: its float rounded to 10 mantissa bits (a relative step of 1e-3,
// far above the 1e-7 of one rounding), mixed so that neighbouring values differ.
uint8_t value_byte(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const uint64_t rounded = (uint64_t(bits) + 0x1000u) >> 13;
  return uint8_t((rounded * 0x9E3779B97F4A7C15ull) >> 56);
}

// A render as the test sees it: a hash of its structure (each view or face file's path
// below the root, size, aoRadius and channel names, which no build may change) and, per
// channel name, the value bytes of every file in listing order.
struct RenderSignature {
  uint64_t structure = 0xcbf29ce484222325ull;
  std::map<std::string, std::string> values;
};

RenderSignature signature_of(const std::string& root) {
  RenderSignature s;
  DatasetListing l = list_dataset(root);
  std::vector<std::string> files;
  for (const SplitListing* split : {&l.train, &l.test, &l.holdout}) {
    for (auto& v : split->views) files.push_back(v);
    for (auto& f : split->frames)
      for (auto& face : f.faces) files.push_back(face);
  }
  EXPECT_FALSE(files.empty()) << root;
  for (const std::string& file : files) {
    std::string rel = fs::path(file).lexically_relative(root).string();
    fnv(s.structure, rel.data(), rel.size());
    View v = read_view(file);
    fnv(s.structure, &v.width, sizeof v.width);
    fnv(s.structure, &v.height, sizeof v.height);
    float radius = v.ao_radius.value_or(-1.0f);
    fnv(s.structure, &radius, sizeof radius);
    for (auto& [name, plane] : v.channels) {
      fnv(s.structure, name.data(), name.size());
      std::string& bytes = s.values[name];
      for (float x : plane) bytes.push_back(char(value_byte(x)));
    }
  }
  return s;
}

// The reference file: the structure hash, then per channel its name and value bytes, each
// preceded by its length as 8 bytes (this machine's byte order: the file is read only by
// this test, on the little-endian machines the project builds for).
void write_signature(const fs::path& path, const RenderSignature& s) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  auto put = [&](const std::string& bytes) {
    const uint64_t n = bytes.size();
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    out.write(bytes.data(), std::streamsize(n));
  };
  out.write(reinterpret_cast<const char*>(&s.structure), sizeof s.structure);
  for (auto& [name, bytes] : s.values) put(name), put(bytes);
  ASSERT_TRUE(out.good()) << path;
}

RenderSignature read_signature(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << path << " is missing: record it with NNSHADE_RECORD_RENDER_REFERENCES=1";
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  RenderSignature s;
  size_t at = 0;
  auto take = [&](void* dst, size_t n) {
    if (at + n > all.size()) throw std::runtime_error(path.string() + ": truncated reference");
    std::memcpy(dst, all.data() + at, n);
    at += n;
  };
  auto take_string = [&] {
    uint64_t n = 0;
    take(&n, sizeof n);
    std::string bytes(n, '\0');
    take(bytes.data(), n);
    return bytes;
  };
  take(&s.structure, sizeof s.structure);
  while (at < all.size()) {
    std::string name = take_string();
    s.values[name] = take_string();
  }
  return s;
}

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

// The share of a channel's values whose byte differs from the reference.
double changed_share(const std::string& got, const std::string& want) {
  size_t changed = 0;
  for (size_t i = 0; i < got.size(); ++i) changed += got[i] != want[i];
  return double(changed) / double(std::max<size_t>(got.size(), 1));
}

// A build that only rounds differently changes at most 1.4% of a channel's values and a
// changed estimator at least 12% (see the top of the file): the bound lies between them.
constexpr double kMaxChangedShare = 0.05;
const char* const kPresets[] = {"nnao", "nnao-v2", "gi", "surround", "surround-v2", "surround-v3", "surround-v4"};
}  // namespace

TEST(RenderFingerprints, ExistingPresetsRenderTheSameNumbers) {
  const bool record = std::getenv("NNSHADE_RECORD_RENDER_REFERENCES") != nullptr;
  set_num_threads(2);
  const fs::path root = temp_root();
  fs::remove_all(root);
  for (const std::string preset : kPresets) {
    DatasetJob job = fingerprint_job(preset, (root / preset).string());
    render_dataset(job);
    const RenderSignature got = signature_of(job.out);
    if (record) {
      write_signature(reference_path(preset), got);
      continue;
    }
    const RenderSignature want = read_signature(reference_path(preset));
    EXPECT_EQ(got.structure, want.structure)
        << preset << ": the files, sizes or channels of an existing preset changed";
    ASSERT_EQ(got.values.size(), want.values.size()) << preset;
    for (auto& [name, bytes] : want.values) {
      auto it = got.values.find(name);
      ASSERT_TRUE(it != got.values.end()) << preset << ": channel " << name << " is gone";
      ASSERT_EQ(it->second.size(), bytes.size()) << preset << " " << name;
      const double share = changed_share(it->second, bytes);
      std::printf("%-12s %-14s %6.2f%% of %zu values changed\n", preset.c_str(), name.c_str(), 100 * share,
                  bytes.size());
      EXPECT_LE(share, kMaxChangedShare) << preset << ": the numbers of channel " << name << " changed";
    }
  }
  fs::remove_all(root);
}
