#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "core/thread_pool.h"

using namespace nns;

namespace {

// Fails the whole binary (instead of hanging ctest until its timeout) if `body` does
// not finish within `seconds`: a lost wake-up in the pool shows up as a hang.
template <class F>
void within_seconds(int seconds, const char* what, F&& body) {
  std::atomic<bool> done{false};
  std::thread watchdog([&] {
    for (int i = 0; i < seconds * 100 && !done; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!done) {
      std::fprintf(stderr, "FAILED: %s did not finish within %d s (deadlock)\n", what, seconds);
      std::_Exit(1);
    }
  });
  body();
  done = true;
  watchdog.join();
}

// Every index of [0, n) visited exactly once, each range aligned as asked.
void check_cover(int64_t n, int64_t min_work, int64_t align) {
  std::vector<std::atomic<int>> hits(size_t(std::max<int64_t>(n, 1)));
  std::atomic<bool> misaligned{false};
  parallel_for(
      n,
      [&](int64_t b, int64_t e) {
        if (b % align != 0) misaligned = true;
        for (int64_t i = b; i < e; ++i) hits[size_t(i)]++;
      },
      min_work, align);
  for (int64_t i = 0; i < n; ++i) ASSERT_EQ(hits[size_t(i)].load(), 1) << "n " << n << " index " << i;
  EXPECT_FALSE(misaligned) << "n " << n << " align " << align;
}

}  // namespace

TEST(ThreadPool, ParallelForCoversEveryIndexOnce) {
  within_seconds(30, "ParallelForCoversEveryIndexOnce", [] {
    for (int threads : {1, 2, 1, 2}) {
      set_num_threads(threads);
      EXPECT_EQ(num_threads(), threads);
      for (int64_t n : {0, 1, 2, 3, 7, 64, 1000, 100003}) {
        check_cover(n, 1, 1);
        check_cover(n, 1, 16);
        check_cover(n, 500, 1);
      }
    }
  });
}

TEST(ThreadPool, RunCallsEveryWorkerOnce) {
  within_seconds(30, "RunCallsEveryWorkerOnce", [] {
    set_num_threads(2);
    std::atomic<int> mask{0}, count{0};
    ThreadPool::global().run([&](int w, int nw) {
      EXPECT_EQ(nw, 2);
      mask |= 1 << w;
      ++count;
    });
    EXPECT_EQ(mask.load(), 3);
    EXPECT_EQ(count.load(), 2);
  });
}

TEST(ThreadPool, NestedCallRunsInlineOnTheWorker) {
  within_seconds(30, "NestedCallRunsInlineOnTheWorker", [] {
    set_num_threads(2);
    std::atomic<int> inner_calls{0}, inner_full_range{0};
    ThreadPool::global().run([&](int, int) {
      parallel_for(1000, [&](int64_t b, int64_t e) {
        ++inner_calls;
        if (b == 0 && e == 1000) ++inner_full_range;
      });
    });
    // Each of the two workers ran the inner loop whole, on itself: no nested split.
    EXPECT_EQ(inner_calls.load(), 2);
    EXPECT_EQ(inner_full_range.load(), 2);
  });
}

TEST(ThreadPool, ChunkBoundariesDoNotDependOnTheThreadCount) {
  within_seconds(30, "ChunkBoundaries", [] {
    std::vector<std::vector<int64_t>> seen;
    for (int threads : {1, 2}) {
      set_num_threads(threads);
      std::vector<int64_t> bounds(3 * 11, -1);
      parallel_chunks(103, 10, [&](int64_t c, int64_t b, int64_t e) {
        bounds[size_t(3 * c)] = c;
        bounds[size_t(3 * c + 1)] = b;
        bounds[size_t(3 * c + 2)] = e;
      });
      seen.push_back(bounds);
    }
    EXPECT_EQ(seen[0], seen[1]);
    EXPECT_EQ(seen[0][3 * 10 + 1], 100);
    EXPECT_EQ(seen[0][3 * 10 + 2], 103);
  });
}

TEST(ThreadPool, SwitchingThreadCountsRepeatedly) {
  within_seconds(60, "SwitchingThreadCountsRepeatedly", [] {
    for (int i = 0; i < 200; ++i) {
      set_num_threads(1 + i % 2);
      std::atomic<int64_t> total{0};
      parallel_for(100, [&](int64_t b, int64_t e) { total += e - b; });
      ASSERT_EQ(total.load(), 100);
    }
  });
}

TEST(ThreadPool, SetThreadsRightAfterStart) {
  // A pool resized before its workers have started must not lose the stop signal.
  within_seconds(60, "SetThreadsRightAfterStart", [] {
    for (int i = 0; i < 300; ++i) {
      ThreadPool pool(2);
      pool.set_threads(1);
      pool.set_threads(2);
    }
  });
}

TEST(ThreadPool, RejectsZeroThreads) { EXPECT_THROW(set_num_threads(0), std::invalid_argument); }

TEST(ThreadPool, DynamicForCoversEveryIndexOnceAndSharesUnevenWork) {
  for (int threads : {1, 2})
    for (int64_t n : {1, 2, 3, 7, 180, 181}) {
      set_num_threads(threads);
      std::vector<std::atomic<int>> hits(static_cast<size_t>(n));
      std::atomic<int> callers_seen{0};
      std::mutex mu;
      std::set<std::thread::id> callers;
      parallel_for_dynamic(n, 2, [&](int64_t b, int64_t e) {
        if (threads == 2) EXPECT_LE(e - b, 2);  // one thread takes the whole range in one call
        for (int64_t i = b; i < e; ++i) hits[size_t(i)]++;
        std::lock_guard<std::mutex> lock(mu);
        callers.insert(std::this_thread::get_id());
        ++callers_seen;
      });
      for (int64_t i = 0; i < n; ++i)
        ASSERT_EQ(hits[size_t(i)].load(), 1) << threads << " threads, n " << n << ", index " << i;
      EXPECT_EQ(callers_seen.load(), threads == 1 || n <= 2 ? 1 : int((n + 1) / 2)) << n;
    }
  // The point of it: when the first half of the items is costly (rows of geometry) and
  // the second free (sky), both workers still take part in the costly half. An even
  // split would give all of it to one worker.
  set_num_threads(2);
  std::mutex mu;
  std::set<std::thread::id> costly;
  parallel_for_dynamic(64, 2, [&](int64_t b, int64_t) {
    if (b >= 32) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::lock_guard<std::mutex> lock(mu);
    costly.insert(std::this_thread::get_id());
  });
  EXPECT_EQ(costly.size(), 2u);
}

// A call shorter than a scheduler tick in which the worker does fixed work (about 0.5 ms)
// and the caller none: the pool's clock counts the worker's share, read from the worker's
// own clock. (The process clock adds a running thread's time only when the scheduler
// accounts it; eval-ao timed through it saw 1.0 threads busy for methods that ran twice
// as fast on 2 threads as on 1. That lag depends on the scheduler's state and is not
// reproduced here.)
TEST(ThreadPool, CpuClockCountsTheWorkersShareOfAShortCall) {
  auto own_cpu_ms = [] {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
  };
  std::atomic<uint64_t> sink{0};
  auto work = [&] {
    uint64_t x = 1;
    for (int i = 0; i < 400000; ++i) x = x * 6364136223846793005ull + 1442695040888963407ull;
    sink += x;
  };
  const double t0 = own_cpu_ms();
  work();
  const double share = own_cpu_ms() - t0;
  set_num_threads(2);
  for (int round = 0; round < 5; ++round) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // the worker goes to sleep
    const double pool0 = pool_cpu_ms(), own0 = own_cpu_ms();
    ThreadPool::global().run([&](int w, int) {
      if (w == 1) work();
    });
    const double workers = (pool_cpu_ms() - pool0) - (own_cpu_ms() - own0);
    EXPECT_GE(workers, 0.8 * share) << "round " << round << ", the share " << share << " ms";
  }
}
