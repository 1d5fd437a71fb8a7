// render_dataset end to end: small nnao and surround datasets that the validator
// passes, disjoint train/test scenes, path-ordered names, reproducible pixels; the
// default dataset's cache folder rules.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/thread_pool.h"
#include "data/dataset.h"
#include "render/default_dataset.h"
#include "data/exr_io.h"
#include "render/dataset_writer.h"
#include "data/validate.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;
namespace fs = std::filesystem;

namespace {
std::string temp_dir(const std::string& name) {
  auto d = fs::temp_directory_path() / ("nnshade-render-dataset-" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  return d.string();
}

DatasetJob tiny(const std::string& preset, const std::string& out) {
  DatasetJob job;
  job.preset = preset;
  job.out = out;
  job.views = 5;
  job.views_per_scene = 2;
  job.width = 24, job.height = 16;
  job.families = {"room", "floating"};
  job.settings.ao_spp = 8, job.settings.gi_spp = 4, job.settings.light_spp = 1;
  job.progress = false;
  return job;
}

// Removes this process's temporary folder after the last test.
class RemoveTempDir : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignore;
    std::filesystem::remove_all(
        std::filesystem::temp_directory_path() / ("nnshade-render-dataset-" + std::to_string(::getpid())), ignore);
  }
};
const auto* const kRemoveTempDir = ::testing::AddGlobalTestEnvironment(new RemoveTempDir);
}  // namespace

TEST(RenderDataset, NnaoValidatesWithDisjointScenes) {
  std::string out = temp_dir("nnao");
  DatasetReport r = render_dataset(tiny("nnao", out));
  EXPECT_EQ(r.train_views + r.test_views, 5);
  EXPECT_GE(r.test_views, 1);
  std::set<std::string> train(r.train_scenes.begin(), r.train_scenes.end());
  for (auto& s : r.test_scenes) EXPECT_EQ(train.count(s), 0u) << s << " is in both splits";
  ValidationReport v = validate_dataset(out, {Purpose::nnao});
  for (auto& p : v.problems) ADD_FAILURE() << p.str();
  EXPECT_TRUE(v.clean());
  DatasetListing l = list_dataset(out);
  ASSERT_FALSE(l.train.views.empty());
  View view = read_view(l.train.views[0]);
  EXPECT_TRUE(view.has("AO") && view.has("N.Z") && !view.has("indirect.R"));
  EXPECT_EQ(view.width, 24);
  ASSERT_TRUE(view.ao_radius.has_value());
  // The same job renders the same pixels.
  std::string again = temp_dir("nnao-again");
  DatasetJob job = tiny("nnao", again);
  render_dataset(job);
  View twin = read_view((fs::path(again) / fs::path(l.train.views[0]).lexically_relative(out)).string());
  EXPECT_EQ(view.channel("AO"), twin.channel("AO"));
  fs::remove_all(again);
}

TEST(RenderDataset, SurroundFramesInPathOrder) {
  std::string out = temp_dir("surround");
  DatasetJob job = tiny("surround", out);
  job.width = job.height = 12;
  job.views = 6;
  job.path_frames = 3;
  job.views_per_scene = 3;
  DatasetReport r = render_dataset(job);
  EXPECT_EQ(r.train_views + r.test_views, 6);
  ValidationReport v = validate_dataset(out, {Purpose::gi});
  for (auto& p : v.problems) ADD_FAILURE() << p.str();
  DatasetListing l = list_dataset(out);
  ASSERT_EQ(l.train.frames.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(l.train.frames[i].complete());
    EXPECT_NE(l.train.frames[i].dir.find("-p00-f00" + std::to_string(i)), std::string::npos) << l.train.frames[i].dir;
  }
  View front = read_view(l.train.frames[0].faces[0]), back = read_view(l.train.frames[0].faces[1]);
  EXPECT_TRUE(front.has("indirect.R"));
  EXPECT_FALSE(back.has("indirect.R"));
  EXPECT_TRUE(back.has("direct.R"));
  EXPECT_EQ(front.fov_y_deg, 90.0f);
}

// Files are written on a thread of their own while the next view renders: a frame that
// cannot be written (a file where its folder goes) still stops the job, naming it.
TEST(RenderDataset, AFrameThatCannotBeWrittenStopsTheJobNamingIt) {
  DatasetJob job = tiny("surround", temp_dir("write-a"));
  job.width = job.height = 12;
  job.views = 4;
  job.path_frames = 2;
  job.views_per_scene = 2;
  render_dataset(job);
  std::set<std::string> frames;
  for (auto& e : fs::directory_iterator(fs::path(job.out) / "train")) frames.insert(e.path().filename().string());
  ASSERT_GE(frames.size(), 2u);
  const std::string blocked = *frames.rbegin();  // not the first: a later write fails
  job.out = temp_dir("write-b");
  fs::create_directories(fs::path(job.out) / "train");
  std::ofstream(fs::path(job.out) / "train" / blocked) << "not a folder";
  try {
    render_dataset(job);
    ADD_FAILURE() << "rendered";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(blocked), std::string::npos) << e.what();
  }
}

TEST(RenderDataset, BadJobsFailWithAReason) {
  DatasetJob job = tiny("nnao", temp_dir("bad"));
  job.families = {"castle"};
  EXPECT_THROW(render_dataset(job), std::invalid_argument);
  job = tiny("pix2pix", temp_dir("bad"));
  EXPECT_THROW(render_dataset(job), std::invalid_argument);
}

TEST(DefaultDataset, RenderedOnceAndRenamedWhenComplete) {
  std::string root = temp_dir("cache");
  fs::create_directories(fs::path(root) / "tiny.partial-999999999");  // a dead process's debris
  std::string dir = ensure_rendered_dataset(tiny("nnao", ""), root, "tiny", 2);
  EXPECT_EQ(dir, (fs::path(root) / "tiny").string());
  EXPECT_TRUE(fs::exists(fs::path(dir) / "COMPLETE"));
  EXPECT_FALSE(fs::exists(fs::path(root) / "tiny.partial-999999999"));
  for (auto& e : fs::directory_iterator(root)) EXPECT_EQ(e.path().filename(), "tiny");
  // The second call finds it and renders nothing.
  auto stamp = fs::last_write_time(fs::path(dir) / "COMPLETE");
  EXPECT_EQ(ensure_rendered_dataset(tiny("nnao", ""), root, "tiny", 2), dir);
  EXPECT_EQ(fs::last_write_time(fs::path(dir) / "COMPLETE"), stamp);
  // A folder without the marker (an old interrupted layout) is not taken as done.
  fs::remove(fs::path(dir) / "COMPLETE");
  EXPECT_THROW(ensure_rendered_dataset(tiny("nnao", ""), root, "tiny", 2), std::runtime_error);
}

TEST(DefaultDataset, CacheRootAndSizes) {
  const char* old = std::getenv("NNSHADE_CACHE");
  std::string saved = old ? old : "";
  setenv("NNSHADE_CACHE", "/tmp/nns-cache-test", 1);
  EXPECT_EQ(default_cache_root(), "/tmp/nns-cache-test");
  unsetenv("NNSHADE_CACHE");
  setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
  EXPECT_EQ(default_cache_root(), "/tmp/xdg/nnshade");
  if (!saved.empty()) setenv("NNSHADE_CACHE", saved.c_str(), 1);
  for (std::string p : {"nnao", "surround", "gi"}) {
    DatasetJob j = default_dataset_job(p);
    EXPECT_GE(j.views, 100) << p;
    // nnao v3+: generations 1-2; surround v5+: all four generations, textured, face 128
    EXPECT_EQ(j.preset, p == "nnao" ? std::string("nnao-v2") : p == "surround" ? std::string("surround-v5") : p);
  }
  EXPECT_EQ(default_dataset_job("surround").width, 128);
  EXPECT_EQ(default_dataset_version("surround"), 6);
  // Version 6: training targets at 64 paths, the references of test/ and holdout/ at 128.
  EXPECT_EQ(default_dataset_job("surround").settings.gi_spp, 128);
  EXPECT_EQ(default_dataset_job("surround").train_gi_spp, 64);
  EXPECT_FALSE(default_dataset_job("surround").holdout_families.empty());
  EXPECT_FALSE(default_dataset_job("nnao").holdout_families.empty());
  EXPECT_GT(default_dataset_job("nnao").path_frames, 1);  // flicker on the default data
  EXPECT_THROW(default_dataset_job("nope"), std::invalid_argument);
}

// surround-v2: cube frames over both generations of families with materials and lights
// varied per scene, recorded in metadata.txt; the same job renders the same bytes.
TEST(RenderDataset, SurroundV2VariesLightingAndRecordsIt) {
  std::string a = temp_dir("sv2a"), b = temp_dir("sv2b");
  for (auto* out : {&a, &b}) {
    DatasetJob job = tiny("surround-v2", *out);
    job.families = {"room", "lounge"};
    job.width = job.height = 8;
    job.views = 4;
    job.views_per_scene = 1;
    render_dataset(job);
  }
  std::ifstream m(a + "/metadata.txt");
  std::stringstream meta;
  meta << m.rdbuf();
  EXPECT_NE(meta.str().find("preset: surround-v2"), std::string::npos) << meta.str();
  EXPECT_NE(meta.str().find("lighting-variation:"), std::string::npos) << meta.str();
  DatasetListing l = list_dataset(a);
  ASSERT_FALSE(l.train.frames.empty());
  View va = read_view(l.train.frames[0].faces[0]);
  View vb = read_view(list_dataset(b).train.frames[0].faces[0]);
  EXPECT_EQ(va.channel("albedo.R"), vb.channel("albedo.R"));
  EXPECT_EQ(va.channel("indirect.G"), vb.channel("indirect.G"));
  // The plain surround preset writes metadata too (its views are what they were:
  // test_render_fingerprints), without the variation.
  std::string c = temp_dir("sv2c");
  DatasetJob plain = tiny("surround", c);
  plain.families = {"room", "lounge"};
  plain.width = plain.height = 8;
  plain.views = 4;
  plain.views_per_scene = 1;
  render_dataset(plain);
  ValidationReport vc = validate_dataset(c, {});
  EXPECT_TRUE(vc.clean());
  EXPECT_EQ(vc.metadata["preset"], "surround");
  EXPECT_EQ(vc.metadata["views.train"], "3");
  EXPECT_EQ(vc.metadata["views.test"], "1");
  EXPECT_EQ(vc.metadata.count("lighting-variation"), 0u);
}

// --noise-seed: the same scenes, cameras and lighting with independent noise (a
// reference against which to measure an estimator must not share its noise); the
// noise seed equal to the seed renders the job's own bytes.
TEST(RenderDataset, NoiseSeedChangesTheNoiseAlone) {
  auto front = [](const std::string& out, int64_t noise_seed) {
    DatasetJob job = tiny("surround-v2", out);
    job.families = {"room"};
    job.width = job.height = 8;
    job.views = 2;
    job.views_per_scene = 1;
    job.settings.seed = 7;
    job.noise_seed = noise_seed;
    render_dataset(job);
    return read_view(list_dataset(out).train.frames.at(0).faces[0]);
  };
  std::string other_dir = temp_dir("ns-other");
  View plain = front(temp_dir("ns-plain"), -1), same = front(temp_dir("ns-same"), 7), other = front(other_dir, 8);
  for (const char* c : {"Z", "N.Y", "albedo.R", "AO", "indirect.G"}) EXPECT_EQ(plain.channel(c), same.channel(c)) << c;
  for (const char* c : {"Z", "N.Y", "albedo.R"}) EXPECT_EQ(plain.channel(c), other.channel(c)) << c;
  for (const char* c : {"AO", "indirect.G"}) EXPECT_NE(plain.channel(c), other.channel(c)) << c;
  std::ifstream m(other_dir + "/metadata.txt");
  std::stringstream meta;
  meta << m.rdbuf();
  EXPECT_NE(meta.str().find("noise-seed: 8"), std::string::npos) << meta.str();
}

// --train-gi-spp: train/ rendered as a job at that many paths, test/ and holdout/ as a
// job at --gi-spp, bit for bit (so a default job can be scored against the references of
// a render at --gi-spp alone); metadata.txt says so.
TEST(RenderDataset, TrainGiSppRendersTrainAloneWithFewerPaths) {
  auto job_at = [](const std::string& out, int gi_spp, int train_gi_spp) {
    DatasetJob job = tiny("surround-v5", out);
    job.families = {"room", "arcade"};
    job.holdout_families = {"arcade"};
    job.holdout_fraction = 0.25;
    job.width = job.height = 8;
    job.views = 8;
    job.views_per_scene = 1;
    job.test_fraction = 0.34;
    job.settings.gi_spp = gi_spp;
    job.train_gi_spp = train_gi_spp;
    render_dataset(job);
    return list_dataset(out);
  };
  const std::string mixed_dir = temp_dir("tgs-mixed");
  DatasetListing mixed = job_at(mixed_dir, 16, 4), low = job_at(temp_dir("tgs-low"), 4, 0),
                 high = job_at(temp_dir("tgs-high"), 16, 0);
  auto same = [](const std::vector<FrameEntry>& a, const std::vector<FrameEntry>& b, const char* split) {
    ASSERT_EQ(a.size(), b.size()) << split;
    ASSERT_FALSE(a.empty()) << split;
    for (size_t i = 0; i < a.size(); ++i) {
      View x = read_view(a[i].faces[0]), y = read_view(b[i].faces[0]);
      for (const char* c : {"Z", "albedo.R", "env.G", "indirect.G"})
        EXPECT_EQ(x.channel(c), y.channel(c)) << split << " frame " << i << " " << c;
    }
  };
  same(mixed.train.frames, low.train.frames, "train");
  same(mixed.test.frames, high.test.frames, "test");
  same(mixed.holdout.frames, high.holdout.frames, "holdout");
  EXPECT_NE(read_view(low.train.frames[0].faces[0]).channel("indirect.G"),
            read_view(high.train.frames[0].faces[0]).channel("indirect.G"));
  std::ifstream m(mixed_dir + "/metadata.txt");
  std::stringstream meta;
  meta << m.rdbuf();
  EXPECT_NE(meta.str().find("gi-spp.train: 4 env and indirect paths per pixel on train/ (16 on test/ and holdout/)"),
            std::string::npos)
      << meta.str();
}

// Leave-families-out: the held-out families render only into holdout/, with instances
// of their own; metadata.txt says which families are where; the validator agrees.
TEST(RenderDataset, HoldoutFamiliesGoOnlyToHoldout) {
  std::string out = temp_dir("holdout");
  DatasetJob job = tiny("nnao", out);
  job.families = {"room", "floating", "thin"};
  job.holdout_families = {"thin"};
  job.views = 8;
  job.holdout_fraction = 0.25;
  DatasetReport r = render_dataset(job);
  EXPECT_EQ(r.train_views + r.test_views + r.holdout_views, 8);
  EXPECT_EQ(r.holdout_views, 2);
  ASSERT_FALSE(r.holdout_scenes.empty());
  for (auto& s : r.holdout_scenes) EXPECT_EQ(s.rfind("thin-2000", 0), 0u) << s;
  for (auto* list : {&r.train_scenes, &r.test_scenes})
    for (auto& s : *list) EXPECT_EQ(s.rfind("thin", 0), std::string::npos) << s << " should be held out";
  DatasetListing l = list_dataset(out);
  EXPECT_TRUE(l.has_holdout);
  EXPECT_EQ(l.holdout.views.size(), 2u);
  ValidationReport v = validate_dataset(out, {Purpose::nnao});
  for (auto& p : v.problems) ADD_FAILURE() << p.str();
  EXPECT_TRUE(v.clean());
  EXPECT_EQ(v.views["holdout"], 2);
  ASSERT_TRUE(v.has_metadata);
  EXPECT_EQ(v.split_families["holdout"], std::vector<std::string>{"thin"});
  EXPECT_EQ(v.split_families["train"], (std::vector<std::string>{"room", "floating"}));
  EXPECT_EQ(v.metadata["preset"], "nnao");
  // Held-out views change nothing about the others: train/ is what the same job
  // without the holdout family renders (same scenes, same cameras, same noise).
  std::string plain = temp_dir("holdout-plain");
  DatasetJob twin = tiny("nnao", plain);
  twin.families = {"room", "floating"};
  twin.views = 6;
  twin.test_fraction = 2.0 / 6;  // the same 2 test views as above (0.2 of 8, rounded)
  render_dataset(twin);
  DatasetListing lp = list_dataset(plain);
  ASSERT_EQ(lp.train.views.size(), l.train.views.size());
  for (size_t i = 0; i < lp.train.views.size(); ++i)
    EXPECT_EQ(read_view(lp.train.views[i]).channel("AO"), read_view(l.train.views[i]).channel("AO")) << i;
  ValidationReport vp = validate_dataset(plain, {});
  EXPECT_TRUE(vp.clean());
  EXPECT_EQ(vp.metadata["preset"], "nnao");
  EXPECT_EQ(vp.metadata.count("families.holdout"), 0u);
  EXPECT_EQ(vp.metadata["views.holdout"], "0");
}

// A leak the validator must catch: a held-out family's scene in train/.
TEST(RenderDataset, ValidatorCatchesAHeldOutFamilyInTrain) {
  std::string out = temp_dir("leak");
  DatasetJob job = tiny("nnao", out);
  job.families = {"room", "floating"};
  job.holdout_families = {"floating"};
  render_dataset(job);
  ASSERT_TRUE(validate_dataset(out, {Purpose::nnao}).clean());
  DatasetListing l = list_dataset(out);
  ASSERT_FALSE(l.holdout.views.empty());
  fs::copy_file(l.holdout.views[0], fs::path(out) / "train" / "moved.exr");
  ValidationReport v = validate_dataset(out, {Purpose::nnao});
  EXPECT_FALSE(v.clean());
  bool named = false;
  for (auto& p : v.problems) named |= p.message.find("held out in metadata.txt, but is in train/") != std::string::npos;
  EXPECT_TRUE(named);
}

TEST(RenderDataset, BadHoldoutListsFailWithAReason) {
  auto fails_with = [](DatasetJob job, const std::string& needle) {
    try {
      render_dataset(job);
      ADD_FAILURE() << "no error, expected '" << needle << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  DatasetJob job = tiny("nnao", temp_dir("bad-holdout"));
  job.holdout_families = {"castle"};
  fails_with(job, "unknown scene family 'castle'");
  job.holdout_families = {"room", "floating"};
  fails_with(job, "leaving none for train/ and test/");
  job.holdout_families = {"room", "room"};
  fails_with(job, "listed twice");
  job.holdout_families = {"thin"};  // a real family, but not among --families room,floating
  fails_with(job, "not among the families rendered");
  job.holdout_families = {"room"};
  job.views = 2;  // 1 test + 1 holdout leaves no train view
  fails_with(job, "leaves no train view");
  job = tiny("nnao", temp_dir("bad-holdout"));
  job.holdout_families = {"room"};
  job.scene_files = {"a.obj", "b.obj"};
  fails_with(job, "cannot be used with --scene");
}

// nnao-v2: every view its own fov, size and AO radius (recorded in its header), the
// second-generation families by default, and still bit-identical for a seed whatever
// the thread count.
TEST(RenderDataset, NnaoV2VariesViewsDeterministically) {
  std::string out = temp_dir("v2");
  DatasetJob job = tiny("nnao-v2", out);
  job.families = {};
  job.views = 10;
  job.views_per_scene = 1;
  job.width = 32, job.height = 18;
  set_num_threads(1);
  DatasetReport r = render_dataset(job);
  EXPECT_EQ(r.train_views + r.test_views, 10);
  ValidationReport v = validate_dataset(out, {Purpose::nnao});
  for (auto& p : v.problems) ADD_FAILURE() << p.str();
  EXPECT_TRUE(v.clean());
  EXPECT_EQ(v.metadata["preset"], "nnao-v2");
  EXPECT_NE(v.metadata["view-variation"].find("fovY 35-90"), std::string::npos);
  // 8 train scenes: the generations interleave, so both are in even a small dataset.
  EXPECT_EQ(v.split_families["train"], (std::vector<std::string>{"room", "lounge", "window-room", "clutter",
                                                                 "colonnade", "stairwell", "stairs", "arcade"}));
  std::set<float> fovs, radii;
  std::set<std::pair<int, int>> sizes;
  DatasetListing l = list_dataset(out);
  std::vector<std::string> all = l.train.views;
  all.insert(all.end(), l.test.views.begin(), l.test.views.end());
  for (auto& path : all) {
    View view = read_view(path);
    EXPECT_GE(view.fov_y_deg, 35.0f);
    EXPECT_LE(view.fov_y_deg, 90.0f);
    ASSERT_TRUE(view.ao_radius.has_value());
    EXPECT_GE(*view.ao_radius, 0.1f);
    EXPECT_LE(*view.ao_radius, 3.0f);
    EXPECT_LE(view.width * view.height, 32 * 18 + 40);  // about 0.6-1.0 of the job's pixels
    EXPECT_GE(view.width * view.height, 32 * 18 / 2);
    fovs.insert(view.fov_y_deg), radii.insert(*view.ao_radius), sizes.insert({view.width, view.height});
  }
  EXPECT_GE(fovs.size(), 8u);
  EXPECT_GE(radii.size(), 8u);
  EXPECT_GE(sizes.size(), 4u);
  std::string again = temp_dir("v2-again");
  job.out = again;
  set_num_threads(2);
  render_dataset(job);
  DatasetListing l2 = list_dataset(again);
  ASSERT_EQ(l2.train.views.size(), l.train.views.size());
  for (size_t i = 0; i < l.train.views.size(); ++i) {
    View a = read_view(l.train.views[i]), b = read_view(l2.train.views[i]);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.channel("AO"), b.channel("AO")) << l.train.views[i];
    EXPECT_EQ(a.channel("N.X"), b.channel("N.X")) << l.train.views[i];
  }
}

// scene.obj and scene.gltf both became scene "scene"; the dataset then had the
// same scene in train/ and test/ and dataset-info rejected what render-dataset wrote.
TEST(RenderDataset, MeshFilesWithTheSameStemAreRefusedBeforeRendering) {
  std::string in = temp_dir("stems"), out = temp_dir("stems-out");
  fs::create_directories(fs::path(in) / "other");
  // A closed 10-unit box with a block inside, as OBJ and (another copy) in a sub-folder.
  const char* box =
      "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nv -5 6 -5\nv 5 6 -5\nv 5 6 5\nv -5 6 5\n"
      "f 1 2 3\nf 1 3 4\nf 5 7 6\nf 5 8 7\nf 1 5 6\nf 1 6 2\nf 2 6 7\nf 2 7 3\nf 3 7 8\nf 3 8 4\nf 4 8 5\nf 4 5 1\n"
      "v -1 0 -1\nv 1 0 -1\nv 1 2 -1\nv -1 2 -1\nf 9 10 11\nf 9 11 12\n";
  std::string a = (fs::path(in) / "scene.obj").string(), b = (fs::path(in) / "other" / "scene.obj").string();
  std::ofstream(a) << box;
  std::ofstream(b) << box;
  DatasetJob job = tiny("nnao", out);
  job.families.clear();
  job.scene_files = {a, b};
  job.views = 4;
  try {
    render_dataset(job);
    ADD_FAILURE() << "two files named scene.* were accepted";
  } catch (const std::exception& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(a), std::string::npos) << m;
    EXPECT_NE(m.find(b), std::string::npos) << m;
    EXPECT_NE(m.find("'scene'"), std::string::npos) << m;
  }
  EXPECT_FALSE(fs::exists(out)) << "output written before the names were checked";
}
