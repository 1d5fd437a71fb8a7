#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include "data/exr_io.h"
#include "data/image_dataset.h"
#include "data/prefetch.h"

using namespace nns;
using namespace nns::data;
namespace fs = std::filesystem;

namespace {

struct Files {
  fs::path dir;
  std::vector<std::string> paths;
  // n views of w x h; every value encodes (view, channel, pixel) so misplaced data shows.
  Files(int n, int w, int h) {
    dir = fs::temp_directory_path() / ("nns_test_image_dataset_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const char* names[] = {"Z", "N.X", "N.Y", "N.Z", "AO"};
    for (int k = 0; k < n; ++k) {
      View v;
      v.width = w;
      v.height = h;
      v.fov_y_deg = 50;
      v.scene = "s";
      for (int c = 0; c < 5; ++c) {
        auto& p = v.add_channel(names[c]);
        for (int i = 0; i < w * h; ++i) p[size_t(i)] = float(k * 10000 + c * 1000 + i);
      }
      paths.push_back((dir / ("v" + std::to_string(k) + ".exr")).string());
      write_view(paths.back(), v);
    }
  }
  ~Files() { fs::remove_all(dir); }
};

ImageDatasetOptions ao_options() {
  ImageDatasetOptions o;
  o.inputs = {"Z", "N.X", "N.Y", "N.Z"};
  o.targets = {"AO"};
  return o;
}

bool same(const Tensor<float>& a, const Tensor<float>& b) {
  return a.shape() == b.shape() && std::equal(a.begin(), a.end(), b.begin());
}

}  // namespace

TEST(ImageDataset, WholeViewsInChannelOrder) {
  Files f(3, 6, 4);
  ImageDataset d(f.paths, ao_options());
  EXPECT_TRUE(d.in_memory());
  EXPECT_EQ(d.bytes_needed(), 3 * 6 * 4 * 5 * 4);
  Batch b = d.batch({2, 0}, Rng(1));
  ASSERT_EQ(b.input.shape(), Shape({2, 4, 4, 6}));
  ASSERT_EQ(b.target.shape(), Shape({2, 1, 4, 6}));
  EXPECT_EQ(b.input[0], 20000.0f);                 // view 2, Z, pixel 0
  EXPECT_EQ(b.input[1 * 24 + 5], 21005.0f);        // view 2, N.X, pixel 5
  EXPECT_EQ(b.input[4 * 24 + 3 * 24 + 23], 3023);  // view 0, N.Z, last pixel
  EXPECT_EQ(b.target[24 + 7], 4007);               // view 0, AO
  EXPECT_EQ(b.info[0].index, 2u);
}

TEST(ImageDataset, CropsComeFromTheRecordedPlace) {
  Files f(2, 9, 7);
  auto o = ao_options();
  o.crop_width = 4, o.crop_height = 3;
  ImageDataset d(f.paths, o);
  Batch b = d.batch({1, 1, 0, 1}, Rng(5));
  ASSERT_EQ(b.input.shape(), Shape({4, 4, 3, 4}));
  bool moved = false;
  for (int j = 0; j < 4; ++j) {
    const SampleInfo& s = b.info[size_t(j)];
    moved |= s.x0 != b.info[0].x0 || s.y0 != b.info[0].y0;
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        float expect = float(int(s.index) * 10000 + 2000 + (s.y0 + y) * 9 + s.x0 + x);  // N.Y
        EXPECT_EQ(b.input[((j * 4 + 2) * 3 + y) * 4 + x], expect);
      }
  }
  EXPECT_TRUE(moved);
}

TEST(ImageDataset, AugmentationTurnsNormalsAndIsReproducible) {
  Files f(2, 8, 8);
  auto o = ao_options();
  o.crop_width = o.crop_height = 5;
  o.augment = true;
  ImageDataset d(f.paths, o);
  Batch a = d.batch({0, 1, 0, 1, 0, 1, 0, 1}, Rng(9));
  Batch again = d.batch({0, 1, 0, 1, 0, 1, 0, 1}, Rng(9));
  EXPECT_TRUE(same(a.input, again.input));
  EXPECT_TRUE(same(a.target, again.target));
  Batch other = d.batch({0, 1, 0, 1, 0, 1, 0, 1}, Rng(10));
  EXPECT_FALSE(same(a.input, other.input));

  // Undo each sample's symmetry by hand: the first pixel of the crop must land where
  // map_pixel says, with (N.X, N.Y) turned by map_vector.
  int turned = 0;
  for (size_t j = 0; j < 8; ++j) {
    const SampleInfo& s = a.info[j];
    turned += s.symmetry.quarter_turns != 0 || s.symmetry.mirror;
    int ox, oy;
    s.symmetry.map_pixel(0, 0, 5, 5, &ox, &oy);
    const int p0 = s.y0 * 8 + s.x0;
    float nx = float(int(s.index) * 10000 + 1000 + p0), ny = float(int(s.index) * 10000 + 2000 + p0);
    s.symmetry.map_vector(&nx, &ny);
    const int64_t base = int64_t(j) * 4 * 25, at = oy * 5 + ox;
    EXPECT_EQ(a.input[base + at], float(int(s.index) * 10000 + p0));  // Z just moves
    EXPECT_EQ(a.input[base + 25 + at], nx);
    EXPECT_EQ(a.input[base + 50 + at], ny);
    EXPECT_EQ(a.target[int64_t(j) * 25 + at], float(int(s.index) * 10000 + 4000 + p0));
  }
  EXPECT_GT(turned, 0);
}

TEST(ImageDataset, StreamingGivesTheSameBatchesAsMemory) {
  Files f(4, 8, 6);
  auto o = ao_options();
  o.crop_width = o.crop_height = 4;
  o.augment = true;
  ImageDataset mem(f.paths, o);
  o.memory_budget_bytes = 0;
  ImageDataset disk(f.paths, o);
  EXPECT_TRUE(mem.in_memory());
  EXPECT_FALSE(disk.in_memory());
  Rng rng(42);
  auto order = mem.shuffled_order(rng);
  Batch a = mem.batch(order, Rng(7)), b = disk.batch(order, Rng(7));
  EXPECT_TRUE(same(a.input, b.input));
  EXPECT_TRUE(same(a.target, b.target));
}

TEST(ImageDataset, ShuffledOrderIsAPermutation) {
  Files f(5, 2, 2);
  ImageDataset d(f.paths, ao_options());
  Rng rng(1);
  auto a = d.shuffled_order(rng), b = d.shuffled_order(rng);
  EXPECT_NE(a, b);
  std::sort(a.begin(), a.end());
  EXPECT_EQ(a, (std::vector<size_t>{0, 1, 2, 3, 4}));
}

TEST(ImageDataset, ErrorsNameTheFileAndChannel) {
  Files f(2, 4, 4);
  auto o = ao_options();
  o.targets = {"indirect.R"};
  try {
    ImageDataset d(f.paths, o);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), f.paths[0] + ": missing channel 'indirect.R' (chosen as target)");
  }
  o.zero_if_missing = {"indirect.R"};
  ImageDataset d(f.paths, o);
  Batch b = d.batch({1}, Rng(0));
  for (float v : b.target) EXPECT_EQ(v, 0.0f);
  o.crop_width = o.crop_height = 5;
  EXPECT_THROW(ImageDataset(f.paths, o), std::runtime_error);
  auto lone = ao_options();
  lone.inputs = {"N.X"};
  lone.augment = true;
  EXPECT_THROW(ImageDataset(f.paths, lone), std::invalid_argument);
}

TEST(Prefetch, DeliversInOrderWhateverTheTiming) {
  std::vector<int> got;
  {
    Prefetcher<int> p(20, [](size_t k) {
      if (k % 3 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
      return int(k * k);
    }, 3);
    while (auto v = p.next()) {
      got.push_back(*v);
      if (got.size() % 4 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(3));
    }
  }
  ASSERT_EQ(got.size(), 20u);
  for (int k = 0; k < 20; ++k) EXPECT_EQ(got[size_t(k)], k * k);
}

TEST(Prefetch, BoundedQueueAndEarlyStop) {
  std::atomic<size_t> made{0};
  {
    Prefetcher<size_t> p(1000, [&](size_t k) {
      made++;
      return k;
    }, 2);
    EXPECT_EQ(*p.next(), 0u);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    // One taken, at most `depth` waiting, at most one in the making.
    EXPECT_LE(made.load(), 4u);
  }  // destroyed with items pending: must not hang
  EXPECT_LT(made.load(), 1000u);
}

TEST(Prefetch, RethrowsTheProducersError) {
  Prefetcher<int> p(5, [](size_t k) {
    if (k == 2) throw std::runtime_error("view 2: broken");
    return int(k);
  });
  EXPECT_EQ(*p.next(), 0);
  EXPECT_EQ(*p.next(), 1);
  try {
    p.next();
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "view 2: broken");
  }
}

TEST(Prefetch, BatchesFromADatasetMatchDirectCalls) {
  Files f(6, 8, 8);
  auto o = ao_options();
  o.crop_width = o.crop_height = 4;
  o.augment = true;
  o.memory_budget_bytes = 0;  // streaming: the prefetch thread does the EXR decoding
  ImageDataset d(f.paths, o);
  Rng epoch(11);
  auto order = d.shuffled_order(epoch);
  auto make = [&](size_t k) {
    return d.batch({order[2 * k], order[2 * k + 1]}, epoch.fork(k));
  };
  Prefetcher<Batch> p(3, make);
  for (size_t k = 0; k < 3; ++k) {
    auto b = p.next();
    ASSERT_TRUE(b.has_value());
    EXPECT_TRUE(same(b->input, make(k).input));
  }
  EXPECT_FALSE(p.next().has_value());
}
