// The views a trainer keeps from the dataset check (data/kept_views.h): the same values
// the file gives when read again, nothing past the budget, and a check whose reads run
// on two threads reporting exactly what it reports on one.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/thread_pool.h"
#include "data/exr_io.h"
#include "data/kept_views.h"
#include "data/require_valid_dataset.h"
#include "data/validate.h"

using namespace nns::data;
namespace fs = std::filesystem;

namespace {

View ramp_view(const std::string& scene, float offset) {
  View v;
  v.width = v.height = 4;
  v.fov_y_deg = 50;
  v.scene = scene;
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z", "AO"}) v.add_channel(c);
  v.ao_radius = 1.0f;
  for (size_t i = 0; i < 16; ++i) {
    v.channels["Z"][i] = 2 + offset + 0.1f * float(i);
    v.channels["N.Z"][i] = 1;
    v.channels["AO"][i] = 0.5f;
  }
  return v;
}

struct Folder {
  fs::path path = fs::temp_directory_path() / ("nns_test_kept_" + std::to_string(getpid()));
  Folder() {
    fs::remove_all(path);
    for (int i = 0; i < 5; ++i)
      write(std::string("train/v") + char('0' + i) + ".exr", ramp_view("s" + std::to_string(i), float(i)));
    write("test/t.exr", ramp_view("u", 9));
  }
  ~Folder() { fs::remove_all(path); }
  std::string file(const std::string& rel) const { return (path / rel).string(); }
  void write(const std::string& rel, const View& v) const {
    fs::create_directories((path / rel).parent_path());
    write_view(file(rel), v);
  }
};

}  // namespace

TEST(KeptViews, TheCheckHandsOverWhatReadingTheFileAgainGives) {
  Folder d;
  const std::vector<std::string> wanted = {d.file("train/v1.exr"), d.file("train/v3.exr")};
  KeptViews kept(wanted, 1e9);
  require_valid_dataset(d.path.string(), Purpose::nnao, &kept);
  ASSERT_TRUE(kept.complete()) << kept.reason();
  EXPECT_EQ(kept.gib() * double(1 << 30), 2.0 * 5 * 16 * sizeof(float));  // two views, five planes each
  for (auto& path : wanted) {
    const View again = read_view(path);
    EXPECT_EQ(kept.get(path).channels, again.channels) << path;
    EXPECT_EQ(kept.get(path).scene, again.scene);
  }
  const View v = kept.take(wanted[0]);
  EXPECT_EQ(v.channels, read_view(wanted[0]).channels);
  EXPECT_EQ(kept.gib() * double(1 << 30), 5.0 * 16 * sizeof(float));  // the taken view no longer counts
}

TEST(KeptViews, KeepsNothingWhenTheViewsWouldPassTheBudget) {
  Folder d;
  // Room for one view of the two: known from the first, before the second is read.
  KeptViews kept({d.file("train/v1.exr"), d.file("train/v3.exr")}, 5 * 16 * sizeof(float) + 1);
  require_valid_dataset(d.path.string(), Purpose::nnao, &kept);
  EXPECT_FALSE(kept.complete());
  EXPECT_NE(kept.reason().find("memory budget"), std::string::npos) << kept.reason();
  EXPECT_EQ(kept.gib(), 0.0);
}

TEST(KeptViews, AViewThatCannotBeShrunkStopsKeepingWithItsReason) {
  Folder d;
  KeptViews kept({d.file("train/v2.exr")}, 1e9, [](View&& v) -> View {
    throw std::runtime_error(v.source + ": --size 3 must divide the view size 4");
  });
  require_valid_dataset(d.path.string(), Purpose::nnao, &kept);  // the check itself passes
  EXPECT_FALSE(kept.complete());
  EXPECT_NE(kept.reason().find("--size 3 must divide"), std::string::npos) << kept.reason();
}

// The check decodes files on the pool's workers; the problems, the summaries and the
// order views are handed over stay those of one thread.
TEST(KeptViews, TheCheckReportsTheSameWithOneThreadOrTwo) {
  Folder d;
  View bad = ramp_view("s1", 1);
  bad.channels["AO"][3] = -1;
  d.write("train/v1.exr", bad);
  std::ofstream(d.file("train/v3.exr")) << "not an exr";
  auto report = [&](int threads, std::vector<std::string>& order) {
    nns::set_num_threads(threads);
    ValidateOptions o;
    o.purpose = Purpose::nnao;
    o.on_view = [&](View&& v) { order.push_back(v.source); };
    ValidationReport r = validate_dataset(d.path.string(), o);
    std::vector<std::string> out;
    for (auto& p : r.problems) out.push_back(p.str());
    return out;
  };
  std::vector<std::string> order1, order2;
  const auto one = report(1, order1), two = report(2, order2);
  nns::set_num_threads(1);
  EXPECT_EQ(one, two);
  EXPECT_EQ(order1, order2);
  EXPECT_GE(one.size(), 2u);
  ASSERT_EQ(order1.size(), 5u);  // v3 unreadable; v0 v1 v2 v4 t in listing order
  EXPECT_EQ(order1.front(), d.file("train/v0.exr"));
  EXPECT_EQ(order1.back(), d.file("test/t.exr"));
}
