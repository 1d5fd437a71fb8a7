// The classical methods' explicit parameters (params.h) and their tuning (tune.h).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <future>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "classical_ao/params.h"
#include "classical_ao/tune.h"
#include "fixtures/synthetic_gbuffer.h"

using namespace nns;

TEST(ClassicalAoParams, DefaultsAreBitwiseTheMethodsAsRegistered) {
  // Parameters must change nothing until a tuned value is chosen.
  auto v = nns::fixtures::synthetic_view(70, 40, 1, 8);
  auto g = screen_space::gbuffer_from_view(v);
  const classical_ao::ClassicalParams defaults;
  for (auto& m : classical_ao::classical_methods())
    for (int n : m.sample_counts) {
      std::vector<float> a(size_t(g.pixels())), b(a.size()), c(a.size()), d(a.size());
      m.run(g, n, a.data());
      classical_ao::run_classical(m.name, defaults, g, n, b.data());
      EXPECT_EQ(a, b) << m.name << "@" << n;
      m.reference(g, n, c.data());
      classical_ao::run_classical(m.name, defaults, g, n, d.data(), true);
      EXPECT_EQ(c, d) << m.name << "@" << n << " reference";
    }
}

TEST(ClassicalAoParams, VectorisedMatchesReferenceAwayFromDefaults) {
  auto v = nns::fixtures::synthetic_view(100, 60, 2, 8);
  auto g = screen_space::gbuffer_from_view(v);
  classical_ao::ClassicalParams p;
  // Every parameter moved to a quarter of the way into its interval.
  for (auto& t : classical_ao::tunables(p)) *t.value = t.lo + 0.25f * (t.hi - t.lo);
  for (auto& m : classical_ao::classical_methods()) {
    std::vector<float> a(size_t(g.pixels())), b(a.size());
    classical_ao::run_classical(m.name, p, g, 16, a.data());
    classical_ao::run_classical(m.name, p, g, 16, b.data(), true);
    double sum = 0;
    size_t off = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]), off += std::abs(a[i] - b[i]) > 1e-5f;
    // As test_classical_ao's comparison: almost every pixel equal to float precision.
    EXPECT_LE(double(off), 0.005 * double(a.size())) << m.name;
    EXPECT_LT(sum / double(a.size()), 1e-4) << m.name;
  }
}

TEST(ClassicalAoParams, FileRoundTripsAndRejectsBadLines) {
  classical_ao::ClassicalParams p;
  p.hbao.angle_bias = 0.123456789f, p.gtao.thickness = 1.5f, p.alchemy.kappa = 0.7f;
  const std::string path = ::testing::TempDir() + "classical_params_test.txt";
  {
    std::ofstream f(path);
    f << classical_ao::format_classical_params(p, "test");
  }
  classical_ao::ClassicalParams q = classical_ao::read_classical_params(path);
  EXPECT_EQ(classical_ao::format_classical_params(q), classical_ao::format_classical_params(p));
  EXPECT_EQ(q.hbao.angle_bias, p.hbao.angle_bias);
  for (const char* bad : {"HBAO.nonsense 1\n", "HBAO.angle_bias\n", "HBAO.angle_bias 99\n", "GTAO.falloff 0.5 7\n"}) {
    {
      std::ofstream f(path);
      f << "# ok\n" << bad;
    }
    try {
      classical_ao::read_classical_params(path);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path + ":2:"), std::string::npos) << e.what();
    }
  }
  std::remove(path.c_str());
}

// eval-ao --classical-params /dev/zero grew to the memory limit and then silently used
// the built-in parameters: a device, a FIFO or a file above the limit is an error naming
// it, never a fallback.
TEST(ClassicalAoParams, AFileThatIsNoRegularFileOrTooLargeIsAnErrorNotTheDefaults) {
  const std::string big = ::testing::TempDir() + "classical_params_big.txt";
  {
    std::ofstream f(big);
    f << classical_ao::format_classical_params(classical_ao::ClassicalParams{});
    for (int i = 0; i < 40000; ++i) f << "# a comment line that makes the file larger than any parameter file\n";
  }
  const std::string fifo = ::testing::TempDir() + "classical_params_fifo.txt";
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {std::string("/dev/null"), big, fifo}) {
    auto read = std::async(std::launch::async, [&]() -> std::string {
      try {
        classical_ao::read_classical_params(path);
      } catch (const std::runtime_error& e) {
        return e.what();
      }
      return "";
    });
    if (read.wait_for(std::chrono::seconds(5)) != std::future_status::ready) {
      ADD_FAILURE() << "reading " << path << " blocks";
      int fd = ::open(path.c_str(), O_WRONLY);  // lets the blocked reader go on
      if (fd >= 0) ::close(fd);
    }
    const std::string e = read.get();
    EXPECT_NE(e.find(path), std::string::npos) << path << ": " << e;
    EXPECT_NE(e.find("1 MiB"), std::string::npos) << "the limit is stated: " << e;
  }
  std::remove(big.c_str());
  std::remove(fifo.c_str());
}

TEST(ClassicalAoParams, TuningLowersTheErrorItMinimises) {
  // Two small views; HBAO started far from its best (a huge angle bias hides all
  // occlusion) must come back down, and the reported error must be the error of the
  // parameters it leaves behind.
  std::vector<data::View> views = {nns::fixtures::synthetic_view(48, 32, 1, 32),
                                   nns::fixtures::synthetic_view(48, 32, 3, 32)};
  classical_ao::ClassicalParams p;
  p.hbao.angle_bias = 0.6f;
  const std::vector<int> counts = {16};
  auto r = classical_ao::tune_classical("HBAO", counts, views, p, 2);
  std::printf("[tune] HBAO: MSE %.5f -> %.5f, angle_bias %.3f, radius_scale %.3f, %d sets\n", r.mse_before, r.mse_after,
              p.hbao.angle_bias, p.hbao.radius_scale, r.evaluations);
  EXPECT_LT(r.mse_after, 0.8 * r.mse_before);
  EXPECT_LT(p.hbao.angle_bias, 0.6f);
  EXPECT_DOUBLE_EQ(classical_ao::classical_mse("HBAO", counts, p, views), r.mse_after);
}
