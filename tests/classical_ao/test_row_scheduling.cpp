// The loop every screen-space AO method runs on (screen_space/simd16.h, for_each_block):
// rows of a frame cost unequal time (a sky row nothing, a row of geometry the whole
// march), so both workers must take part in the costly rows wherever they lie. With an
// even split of the rows, a frame whose lower half holds all the geometry ran on one
// thread: 2 threads bought nothing at 320x180.
#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "core/thread_pool.h"
#include "screen_space/ao_common.h"
#include "screen_space/simd16.h"

using namespace nns;

namespace {

// 64 x 40: rows 0..31 sky, rows 32..39 a plane: the costly rows are the last fifth.
struct SkyAbovePlane {
  std::vector<float> z, n0, n1;
  screen_space::GBuffer g;
  SkyAbovePlane() : z(64 * 40, INFINITY), n0(z.size(), 0), n1(z.size(), 1) {
    for (size_t i = 32 * 64; i < z.size(); ++i) z[i] = 3;
    g = screen_space::make_gbuffer(64, 40, 60, 1, z.data(), n0.data(), n0.data(), n1.data());
  }
};

template <class Loop>
std::set<std::thread::id> threads_on_costly_rows(const screen_space::GBuffer& g, Loop loop) {
  std::mutex mu;
  std::set<std::thread::id> ids;
  loop(g, [&](int y) {
    if (g.sky(int64_t(y) * g.width)) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(3));  // a row of geometry costs
    std::lock_guard<std::mutex> lock(mu);
    ids.insert(std::this_thread::get_id());
  });
  return ids;
}

}  // namespace

TEST(RowScheduling, BothWorkersShareTheRowsThatCost) {
  set_num_threads(2);
  const SkyAbovePlane f;
  const auto blocks = threads_on_costly_rows(f.g, [](const screen_space::GBuffer& g, auto row) {
    screen_space::simd::for_each_block(g, [&](int x0, int y, screen_space::simd::Mask) {
      if (x0 == 0) row(y);
    });
  });
  EXPECT_EQ(blocks.size(), 2u) << "for_each_block ran the costly rows on one worker";
  const auto pixels = threads_on_costly_rows(f.g, [](const screen_space::GBuffer& g, auto row) {
    screen_space::for_each_pixel(g, [&](int x, int y, int64_t) {
      if (x == 0) row(y);
    });
  });
  EXPECT_EQ(pixels.size(), 2u) << "for_each_pixel ran the costly rows on one worker";
}
