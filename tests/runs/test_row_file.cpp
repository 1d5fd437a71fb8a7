// The on-disk training points (runs/ao/row_file.h, runs/ao/nnao_points.h): the
// chunked shuffle visits every row once per epoch through buffers no larger than asked,
// a buffer holding everything reproduces the global Fisher-Yates draw for draw, the file
// leaves no name behind, and the streamed statistics do not depend on the blocks.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <vector>

#include "core/rng.h"
#include "runs/ao/nnao_points.h"
#include "runs/ao/row_file.h"

namespace fs = std::filesystem;
using nns::Rng;
using nns::runs::RowFile;
using nns::runs::ShuffledRows;

namespace {

fs::path temp_dir() {
  fs::path d = fs::temp_directory_path() / ("nnshade_point_file_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

struct RemoveTempDir : ::testing::Environment {
  void TearDown() override { fs::remove_all(temp_dir()); }
};
const auto* const kRemoveTempDir = ::testing::AddGlobalTestEnvironment(new RemoveTempDir);

// A file of `n` rows of 8 bytes, row i holding the int64 i.
RowFile numbered(const fs::path& dir, int64_t n) {
  RowFile f(dir.string(), "rows", 8);
  for (int64_t i = 0; i < n; ++i) f.append(&i, 1);
  return f;
}

std::vector<int64_t> epoch(ShuffledRows& s, Rng& rng, int64_t n) {
  s.start_epoch(rng);
  std::vector<int64_t> out;
  for (int64_t k = 0; k < n; ++k) {
    int64_t v;
    std::memcpy(&v, s.next(rng), 8);
    out.push_back(v);
  }
  return out;
}

}  // namespace

TEST(PointFile, LeavesNoNameInTheFolderAndReadsBackWhatWasWritten) {
  fs::path dir = temp_dir() / "noname";
  fs::create_directories(dir);
  {
    RowFile f = numbered(dir, 100);
    EXPECT_TRUE(fs::is_empty(dir));  // unlinked at creation: a SIGKILL leaves nothing
    std::vector<int64_t> back(10);
    f.read_rows(40, 10, back.data());
    for (int k = 0; k < 10; ++k) EXPECT_EQ(back[size_t(k)], 40 + k);
    EXPECT_THROW(f.read_rows(95, 10, back.data()), std::out_of_range);
  }
  fs::remove_all(dir);
}

TEST(PointFile, ChunkedShuffleVisitsEveryRowOnceWithABoundedBuffer) {
  const int64_t n = 1000;  // 1000 rows, chunks of 7 (last one short), buffers of 5 chunks
  RowFile f = numbered(temp_dir(), n);
  ShuffledRows s(f, 7, 38);
  EXPECT_EQ(s.rows_per_group(), 35);
  EXPECT_EQ(s.groups(), 29);
  Rng rng(3);
  std::vector<int64_t> a = epoch(s, rng, n), b = epoch(s, rng, n);
  std::vector<int64_t> sorted = a;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int64_t> all(static_cast<size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(sorted, all);
  sorted = b;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, all);
  EXPECT_NE(a, b);  // a new order each epoch
  // The epoch is a sequence of groups, each the rows of whole chunks, at most 5 (the last
  // chunk holds 6 rows, not 7), the groups balanced to within one chunk (143 chunks:
  // 29 groups of 4 or 5, no small remainder group at the end): what makes it a chunked
  // shuffle, and why the memory is two buffers of 35 rows.
  auto chunk_rows = [&](int64_t c) { return std::min<int64_t>(7, n - c * 7); };
  size_t p = 0;
  for (int64_t g = 0; g < s.groups(); ++g) {
    const int64_t k = s.group_begin(g + 1) - s.group_begin(g);
    EXPECT_TRUE(k == 4 || k == 5) << "group " << g << " has " << k << " chunks";
    std::vector<int64_t> seen;
    int64_t rows = 0, expected = 0;
    while (p < a.size() && !(int64_t(seen.size()) == k && rows == expected)) {
      const int64_t c = a[p++] / 7;
      if (std::find(seen.begin(), seen.end(), c) == seen.end()) {
        seen.push_back(c);
        expected += chunk_rows(c);
      }
      ++rows;
      ASSERT_LE(int64_t(seen.size()), k) << "group " << g << " mixes in another group's chunk, at row " << p;
    }
    EXPECT_EQ(rows, expected) << "group " << g << " ends with a chunk half read";
  }
  EXPECT_EQ(p, a.size());
  // The same Rng state replays the same order (what --resume relies on).
  Rng again(3);
  EXPECT_EQ(epoch(s, again, n), a);
}

TEST(PointFile, OneBufferForEverythingIsTheGlobalShuffle) {
  const int64_t n = 500;
  RowFile f = numbered(temp_dir(), n);
  ShuffledRows s(f, 16, 100000);
  Rng rng(9), ref(9);
  for (int e = 0; e < 3; ++e) {  // later epochs reuse the one buffer
    std::vector<int64_t> got = epoch(s, rng, n);
    std::vector<int64_t> perm(static_cast<size_t>(n));
    std::iota(perm.begin(), perm.end(), 0);
    for (int64_t i = n - 1; i > 0; --i) std::swap(perm[size_t(i)], perm[size_t(ref.below(uint64_t(i + 1)))]);
    EXPECT_EQ(got, perm) << "epoch " << e;
    EXPECT_EQ(rng.state(), ref.state());  // and not one draw more
  }
}

TEST(PointFile, StreamedStatisticsDoNotDependOnTheBlocks) {
  using namespace nns::nnao;
  using namespace nns::runs;
  const int64_t F = 12, R = point_row_bytes(F), n = 300;
  std::vector<char> rows(size_t(n * R));
  Rng rng(4);
  for (int64_t i = 0; i < n; ++i) {
    Half* x = row_features(rows.data() + i * R);
    for (int64_t f = 0; f < F; ++f) x[f] = to_half(f == 0 ? 0.0f : float(rng.uniform()) * float(f) - 1.0f);
    set_row_target(rows.data() + i * R, F, float(rng.uniform()));
  }
  StandardizerSums one(F), blocks(F);
  one.add(rows.data(), n);
  for (int64_t b = 0; b < n; b += 77) blocks.add(rows.data() + b * R, std::min<int64_t>(77, n - b));
  const Standardizer a = one.finish(), b = blocks.finish();
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.std, b.std);
  EXPECT_EQ(a.target_mean, b.target_mean);
  EXPECT_EQ(a.std[0], 1.0f);  // a constant feature keeps std 1
  // Against a two-pass reference in double.
  for (int64_t f = 1; f < F; ++f) {
    double m = 0, v = 0;
    for (int64_t i = 0; i < n; ++i) m += double(row_features(rows.data() + i * R)[f]);
    m /= double(n);
    for (int64_t i = 0; i < n; ++i) {
      const double d = double(row_features(rows.data() + i * R)[f]) - m;
      v += d * d;
    }
    EXPECT_NEAR(a.mean[size_t(f)], m, 1e-6 * (1 + std::abs(m)));
    EXPECT_NEAR(a.std[size_t(f)], std::sqrt(v / double(n)), 1e-5);
  }
}

TEST(PointFile, StandardizingTheFileInBlocksEqualsStandardizingTheRows) {
  using namespace nns::nnao;
  using namespace nns::runs;
  const int64_t F = 8, R = point_row_bytes(F), n = 50;
  std::vector<char> rows(size_t(n * R));
  Rng rng(5);
  for (int64_t i = 0; i < n; ++i) {
    for (int64_t f = 0; f < F; ++f) row_features(rows.data() + i * R)[f] = to_half(float(rng.uniform()) * 3);
    set_row_target(rows.data() + i * R, F, float(rng.uniform()));
  }
  StandardizerSums sums(F);
  sums.add(rows.data(), n);
  const Standardizer st = sums.finish();
  PointFile pf;
  pf.features = F;
  pf.rows = RowFile(temp_dir().string(), "std", R);
  pf.rows.append(rows.data(), n);
  standardize_file(pf, st);
  std::vector<char> back(rows.size());
  pf.rows.read_rows(0, n, back.data());
  EXPECT_NE(std::memcmp(back.data(), rows.data(), rows.size()), 0);  // the file was rewritten...
  standardize_rows(rows.data(), n, F, st);
  EXPECT_EQ(std::memcmp(back.data(), rows.data(), rows.size()), 0);  // ...to the standardised rows
}
