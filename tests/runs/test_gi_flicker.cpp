// eval-gi's temporal stability (runs/gi/gi_scores.h, eval_gi.h): on a rendered camera
// path, frames are reprojected onto the one before, so a prediction equal to the truth
// flickers exactly as much as the truth (ratio 1, temporal error 0), per-pixel noise
// raises both, and frames that are not consecutive on one path are never paired.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "core/rng.h"
#include "render/dataset_writer.h"
#include "runs/gi/eval_gi.h"

namespace fs = std::filesystem;
using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

namespace {

std::vector<GiSample> rendered_path(const fs::path& dir) {
  render::DatasetJob job;
  job.out = dir.string();
  job.preset = "surround";
  job.families = {"room"};
  job.views = 6;
  job.path_frames = 3;
  job.views_per_scene = 3;
  job.test_fraction = 0.5;
  job.width = job.height = 64;  // paths drift 2.5-5 cm a frame: at 16 px nothing moves a pixel
  job.settings.ao_spp = 4, job.settings.gi_spp = 16, job.settings.bounces = 2;
  job.progress = false;
  render::render_dataset(job);
  auto listing = data::list_dataset(dir.string());
  GiInputConfig cfg;
  return load_samples(listing.test, GiItemReader{GiMode::surround, 0}, cfg, size_t(-1), "", true);
}

}  // namespace

TEST(GiFlicker, ReprojectedAlongTheCameraPath) {
  const fs::path dir = fs::temp_directory_path() / ("nns_gi_flicker_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  std::vector<GiSample> frames = rendered_path(dir);
  ASSERT_EQ(frames.size(), 3u);
  ASSERT_TRUE(next_on_path(frames[0], frames[1]));
  ASSERT_FALSE(next_on_path(frames[1], frames[0]));
  ASSERT_FALSE(next_on_path(frames[0], frames[2]));
  ASSERT_TRUE(frames[1].front_geometry.world_to_camera.has_value());

  EvalOptions o;
  o.out = (dir / "eval").string();
  o.previews = 0;
  const HdrMapping hdr(0.5f);
  std::string csv;
  EvalRow truth = score(
      "truth", "-", frames, hdr, o, [](const GiSample& s) { return s.target_linear.clone(); }, csv);
  EXPECT_EQ(truth.flicker_pairs, 2);
  EXPECT_GT(truth.flicker_truth, 0);
  EXPECT_DOUBLE_EQ(truth.flicker, truth.flicker_truth);
  EXPECT_EQ(truth.temporal_error, 0);

  Rng rng(5);
  EvalRow noisy = score(
      "noisy", "-", frames, hdr, o,
      [&](const GiSample& s) {
        Tensor<float> p = s.target_linear.clone();
        for (int64_t i = 0; i < p.numel(); ++i) p[i] *= float(rng.uniform(0.7, 1.3));
        return p;
      },
      csv);
  EXPECT_GT(noisy.flicker, 1.2 * noisy.flicker_truth);
  EXPECT_GT(noisy.temporal_error, 0.01);

  // Reprojection matters: the moving camera's own change, counted pixel-to-pixel without
  // it, is more than what the truth changes at the same surface points.
  const auto map = reproject_front(frames[1], frames[0]);
  int64_t mapped_pixels = 0, moved = 0;
  for (size_t i = 0; i < map.size(); ++i)
    if (map[i] >= 0) ++mapped_pixels, moved += map[i] != int64_t(i);
  EXPECT_GT(mapped_pixels, int64_t(map.size()) / 2);
  EXPECT_GT(moved, 0);
  fs::remove_all(dir);
}
