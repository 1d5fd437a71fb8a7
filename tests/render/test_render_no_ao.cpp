// A lit render without the AO channel (--no-ao, the default surround data): no AO
// rays, and every other channel the same bits as the render with AO.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

#include "core/atomic_file.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "render/dataset_writer.h"
#include "render/default_dataset.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;

namespace {
std::string metadata_text(const std::filesystem::path& dir) { return read_file((dir / kMetadataFile).string()); }
}  // namespace

TEST(RenderNoAo, EveryOtherChannelIsTheSameBitsAndTheRaysAreFewer) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("nnshade-no-ao-" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  auto job = [&](bool ao, DatasetReport& report) {
    DatasetJob j;
    j.preset = "surround-v5";
    j.out = (root / (ao ? "ao" : "no-ao")).string();
    j.views = 3, j.views_per_scene = 1, j.width = j.height = 10;
    j.families = {"window-room", "cloister"};
    j.settings.ao_spp = 16, j.settings.gi_spp = 8, j.settings.light_spp = 1, j.settings.side_spp = 4;
    j.settings.ao = ao;
    j.progress = false;
    report = render_dataset(j);
    return list_dataset(j.out);
  };
  DatasetReport with_report, without_report;
  DatasetListing with = job(true, with_report), without = job(false, without_report);
  ASSERT_EQ(with.train.frames.size(), without.train.frames.size());
  ASSERT_GT(with.train.frames.size(), 0u);
  for (size_t f = 0; f < with.train.frames.size(); ++f)
    for (size_t face = 0; face < 6; ++face) {
      View a = read_view(with.train.frames[f].faces[face]), b = read_view(without.train.frames[f].faces[face]);
      EXPECT_TRUE(a.has("AO"));
      EXPECT_FALSE(b.has("AO")) << "face " << face;
      EXPECT_EQ(a.channels.size(), b.channels.size() + 1);
      for (auto& [name, plane] : a.channels)
        if (name != "AO") EXPECT_EQ(plane, b.channel(name)) << name << " of face " << face;
    }
  EXPECT_LT(without_report.rays, with_report.rays);
  EXPECT_NE(metadata_text(root / "no-ao").find("ao: none"), std::string::npos);
  EXPECT_NE(metadata_text(root / "no-ao").find("side-spp: 4 env rays"), std::string::npos);
  EXPECT_EQ(metadata_text(root / "ao").find("ao: none"), std::string::npos);
  std::filesystem::remove_all(root);
}

TEST(RenderNoAo, TheNnaoPresetsRefuseIt) {
  for (const char* preset : {"nnao", "nnao-v2"}) {
    DatasetJob j;
    j.preset = preset;
    j.settings.ao = false;
    EXPECT_THROW(apply_preset(j), std::invalid_argument) << preset;
  }
}

TEST(RenderNoAo, TheDefaultSurroundDataHasNoAoAndTheNnaoDataHasIt) {
  EXPECT_FALSE(default_dataset_job("surround").settings.ao);
  EXPECT_TRUE(default_dataset_job("nnao").settings.ao);
}
