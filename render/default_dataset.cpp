#include "render/default_dataset.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "core/thread_pool.h"

namespace nns::render {

namespace fs = std::filesystem;

DatasetJob default_dataset_job(const std::string& preset) {
  DatasetJob job;
  job.preset = preset;
  job.settings.seed = 20160501;  // fixed: the default dataset is the same everywhere
  job.test_fraction = 0.2;
  if (preset == "nnao") {
    // Every family (nnao-v2: per-view fov, aspect, size, AO radius, pitch) so the model
    // learns geometry in general, with three whole families held out (holdout/: never
    // trained on, eval-ao scores them beside test/) and every view a frame of a 4-frame
    // camera path, so eval-ao measures flicker on the default data. The held-out
    // families are the ones least like the architecture a user's scene holds (cave,
    // pipes, round): arcades, vaults, rooms and stairs stay in training.
    // Version 4: 640 views, so that test/ holds three scenes of every family (192 views
    // = 48 four-frame paths, one scene each, dealt to the 16 families in turn); train/
    // 320 views (5 scenes per family), holdout/ 128. ~0.8 CPU-s per view
    // (docs/renderer.md): about 4-5 minutes on 2 idle cores.
    job.preset = "nnao-v2";
    job.views = 640;
    job.views_per_scene = 4;
    job.path_frames = 4;
    job.test_fraction = 0.3;
    job.holdout_families = {"cave", "pipes", "round"};
    job.holdout_fraction = 0.2;
    job.width = 320, job.height = 180;
    job.fov_y_deg = 60;
    job.settings.ao_spp = 256;
  } else if (preset == "surround") {
    // Cube frames for the surround-aware GAN (version 6): all 24 families with textured
    // materials (surround-v5: surround-v4's procedural textures in the albedo and in the
    // light alike, 32 side-face AO and env rays per pixel at face 128), one 4-frame camera
    // path per scene, so the 2,400 frames come from 600 scenes; cave, pipes and round are
    // held out (holdout/, as the AO data), 15% of the rest is test/, and train-gan carves
    // its validation scenes out of train/. 128x128 faces, the size the light is delivered
    // at: train-gan trains at face 64 (box-filtered) and brings the indirect light back up
    // with the guided upsample, which beat a face-128 network of the same arithmetic on the
    // validation scenes (docs/results/2026-12-05-gi-face128-network-vs-upsample.md).
    // The GI references of test/ and holdout/ take 128 paths on front (per area of a
    // face-64 pixel 0.61x the noise of version 4's 256 paths at face 64,
    // docs/results/2026-12-05-surround-speed.md); the training targets of train/ take 64:
    // over 3 seeds the models trained on them scored inside the seed range of those trained
    // on 128 on the validation scenes (MSE +2.5%, SSIM +0.001), for 0.53x the CPU time of
    // a train/ frame (docs/results/2026-12-06-gi-training-paths.md). Version 5 was this
    // with 128 paths on train/ too, 6,888 CPU-s on an Intel Xeon; version 6 3,957 (35 min
    // on 2 cores).
    job.preset = "surround-v5";
    job.views = 2400;
    job.views_per_scene = 4;
    job.path_frames = 4;
    job.test_fraction = 0.15;
    job.holdout_families = {"cave", "pipes", "round"};
    job.holdout_fraction = 0.15;
    job.width = job.height = 128;
    job.settings.ao_spp = 64;
    job.settings.gi_spp = 128;
    job.train_gi_spp = 64;
    // No AO channel: nothing that trains or scores GI reads it, and its rays (64 on the
    // front face, 32 on each side face) were 14% of a frame's CPU time. Every other
    // channel is the same bits (render_view still draws AO's random numbers), so an
    // earlier version-6 render, which has AO, is as good.
    job.settings.ao = false;
    job.settings.light_spp = 4;
    job.settings.bounces = 3;
  } else if (preset == "gi") {
    // Single views with every lighting channel, 128x128 at a 90-degree fov (the size
    // of a surround front face), 96 train + 24 test. Version 3: the renderer's faster
    // estimator (one-light NEE, roulette) changed the noise, so the pixels.
    job.views = 120;
    job.views_per_scene = 6;
    job.width = job.height = 128;
    job.fov_y_deg = 90;
    job.settings.ao_spp = 64;
    job.settings.gi_spp = 128;
    job.settings.bounces = 3;
  } else {
    throw std::invalid_argument("no default dataset for preset '" + preset + "' (nnao, surround, gi)");
  }
  return job;
}

std::string default_cache_root() {
  if (const char* c = std::getenv("NNSHADE_CACHE"); c && *c) return c;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return (fs::path(x) / "nnshade").string();
  if (const char* h = std::getenv("HOME"); h && *h) return (fs::path(h) / ".cache" / "nnshade").string();
  throw std::runtime_error("default dataset: set NNSHADE_CACHE (no XDG_CACHE_HOME or HOME to find a cache folder)");
}

std::string ensure_default_dataset(const std::string& preset, int threads) {
  return ensure_rendered_dataset(default_dataset_job(preset), default_cache_root(),
                                 "default-" + preset + "-v" + std::to_string(default_dataset_version(preset)), threads);
}

std::string ensure_rendered_dataset(DatasetJob job, const std::string& root_dir, const std::string& name, int threads) {
  fs::path root = root_dir;
  fs::path final_dir = root / name;
  fs::path marker = final_dir / "COMPLETE";
  if (fs::exists(marker)) return final_dir.string();

  fs::create_directories(root);
  // Partial renders of processes that no longer exist are debris of an interrupted run.
  std::string prefix = name + ".partial-";
  for (auto& e : fs::directory_iterator(root)) {
    std::string entry = e.path().filename().string();
    if (entry.rfind(prefix, 0) == 0 && !fs::exists("/proc/" + entry.substr(prefix.size()))) {
      std::error_code ignore;
      fs::remove_all(e.path(), ignore);
    }
  }
  fs::path partial = root / (prefix + std::to_string(::getpid()));
  fs::remove_all(partial);
  std::fprintf(stderr, "dataset '%s' not found in %s: rendering it once (%d %s, %dx%d)\n", name.c_str(),
               root.string().c_str(), job.views, is_surround_preset(job.preset) ? "frames" : "views", job.width,
               is_surround_preset(job.preset) ? job.width : job.height);
  set_num_threads(threads);
  job.out = partial.string();
  DatasetReport r = render_dataset(job);
  {
    std::ofstream m(partial / "COMPLETE");
    m << "nnshade dataset '" << name << "' (preset " << job.preset << "): " << r.train_views << " train + "
      << r.test_views << " test, seed " << job.settings.seed << ", rendered in " << r.total_seconds << " s ("
      << r.cpu_seconds << " CPU-s)\n";
    if (!m) throw std::runtime_error((partial / "COMPLETE").string() + ": cannot write");
  }
  std::error_code ec;
  fs::rename(partial, final_dir, ec);
  if (ec) {
    // Another process may have finished the same dataset first: use theirs.
    if (fs::exists(marker)) {
      fs::remove_all(partial);
      return final_dir.string();
    }
    throw std::runtime_error("cannot rename " + partial.string() + " to " + final_dir.string() + ": " + ec.message());
  }
  std::fprintf(stderr, "dataset ready: %s (%.0f s)\n", final_dir.string().c_str(), r.total_seconds);
  return final_dir.string();
}

}  // namespace nns::render
