#include <gtest/gtest.h>

#include <cfloat>
#include <chrono>
#include <thread>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "core/kernels/gemm.h"
#include "core/rng.h"

using namespace nns;

namespace {

struct Case {
  bool ta, tb;
  int64_t M, N, K;
  float alpha, beta;
  int64_t pad = 0;  // extra columns in every leading dimension
  std::string str() const {
    return "ta=" + std::to_string(ta) + " tb=" + std::to_string(tb) + " M=" + std::to_string(M) +
           " N=" + std::to_string(N) + " K=" + std::to_string(K) + " alpha=" + std::to_string(alpha) +
           " beta=" + std::to_string(beta) + " pad=" + std::to_string(pad);
  }
};

struct Problem {
  std::vector<float> A, B, C0;
  int64_t lda, ldb, ldc;
};

std::vector<float> random_vec(size_t n, Rng& rng) {
  std::vector<float> v(n);
  for (auto& x : v) x = float(rng.normal());
  return v;
}

Problem make_problem(const Case& c, Rng& rng) {
  Problem p;
  const int64_t arows = c.ta ? c.K : c.M, acols = c.ta ? c.M : c.K;
  const int64_t brows = c.tb ? c.N : c.K, bcols = c.tb ? c.K : c.N;
  p.lda = acols + c.pad;
  p.ldb = bcols + c.pad;
  p.ldc = c.N + c.pad;
  p.A = random_vec(size_t(arows * p.lda), rng);
  p.B = random_vec(size_t(brows * p.ldb), rng);
  p.C0 = random_vec(size_t(c.M * p.ldc), rng);
  return p;
}

// Compares gemm<float> against the reference evaluated in double, with the classical
// forward error bound |err| <= gamma_K * (|alpha| |A||B| + |beta C0|), gamma_K ~ (K+2) eps.
void check_against_reference(const Case& c, uint64_t seed) {
  SCOPED_TRACE(c.str());
  Rng rng(seed);
  Problem p = make_problem(c, rng);
  std::vector<float> C = p.C0;
  if (c.beta == 0.0f) std::fill(C.begin(), C.end(), std::numeric_limits<float>::quiet_NaN());
  gemm<float>(c.ta, c.tb, c.M, c.N, c.K, c.alpha, p.A.data(), p.lda, p.B.data(), p.ldb, c.beta, C.data(), p.ldc);

  std::vector<double> Ad(p.A.begin(), p.A.end()), Bd(p.B.begin(), p.B.end());
  std::vector<double> absA(Ad.size()), absB(Bd.size());
  for (size_t i = 0; i < Ad.size(); ++i) absA[i] = std::fabs(Ad[i]);
  for (size_t i = 0; i < Bd.size(); ++i) absB[i] = std::fabs(Bd[i]);
  std::vector<double> ref(p.C0.begin(), p.C0.end()), mag(size_t(c.M * p.ldc), 0.0);
  gemm_reference<double>(c.ta, c.tb, c.M, c.N, c.K, c.alpha, Ad.data(), p.lda, Bd.data(), p.ldb, c.beta, ref.data(),
                         p.ldc);
  gemm_reference<double>(c.ta, c.tb, c.M, c.N, c.K, 1.0, absA.data(), p.lda, absB.data(), p.ldb, 0.0, mag.data(),
                         p.ldc);
  const double gamma = double(c.K + 4) * FLT_EPSILON;
  int bad = 0;
  for (int64_t i = 0; i < c.M; ++i)
    for (int64_t j = 0; j < c.N; ++j) {
      const size_t at = size_t(i * p.ldc + j);
      const double bound = gamma * (std::fabs(c.alpha) * mag[at] + std::fabs(c.beta * p.C0[at])) + 1e-30;
      if (!(std::fabs(C[at] - ref[at]) <= bound) && bad++ < 5)
        ADD_FAILURE() << "C[" << i << "," << j << "] = " << C[at] << ", reference " << ref[at] << ", bound " << bound;
    }
  // Padding columns of C must be left alone.
  for (int64_t i = 0; i < c.M; ++i)
    for (int64_t j = c.N; j < p.ldc; ++j) {
      const size_t at = size_t(i * p.ldc + j);
      const float expect = c.beta == 0.0f ? std::numeric_limits<float>::quiet_NaN() : p.C0[at];
      if (std::memcmp(&C[at], &expect, sizeof(float)) != 0 && bad++ < 5)
        ADD_FAILURE() << "padding C[" << i << "," << j << "] was written";
    }
  EXPECT_EQ(bad, 0);
}

void settle_threads(int n) { set_num_threads(n); }

class ThreadsGuard {
 public:
  ThreadsGuard() : saved_(num_threads()) {}
  ~ThreadsGuard() { settle_threads(saved_); }

 private:
  int saved_;
};

std::vector<float> run_with_threads(int threads, const Case& c, const Problem& p) {
  settle_threads(threads);
  std::vector<float> C = p.C0;
  gemm<float>(c.ta, c.tb, c.M, c.N, c.K, c.alpha, p.A.data(), p.lda, p.B.data(), p.ldb, c.beta, C.data(), p.ldc);
  return C;
}

}  // namespace

TEST(Gemm, AllTransposesOddSizesMatchReference) {
  const int64_t sizes[] = {1, 7, 33, 257};
  uint64_t seed = 1;
  for (int threads : {1, 2}) {
    ThreadsGuard guard;
    settle_threads(threads);
    for (bool ta : {false, true})
      for (bool tb : {false, true})
        for (int64_t M : sizes)
          for (int64_t N : sizes)
            for (int64_t K : sizes) check_against_reference({ta, tb, M, N, K, 1.0f, 0.0f}, seed++);
  }
}

TEST(Gemm, AlphaBetaAndLeadingDimensions) {
  uint64_t seed = 100;
  for (bool ta : {false, true})
    for (bool tb : {false, true})
      for (float alpha : {1.0f, -0.5f, 2.0f})
        for (float beta : {0.0f, 1.0f, 0.25f})
          for (int64_t pad : {0, 3, 17}) check_against_reference({ta, tb, 45, 70, 19, alpha, beta, pad}, seed++);
}

TEST(Gemm, BetaZeroNeverReadsNaNs) {
  // check_against_reference fills C with NaN whenever beta == 0; do it on shapes that
  // take every path: edge tiles, several K blocks, both thread splits.
  ThreadsGuard guard;
  for (int threads : {1, 2}) {
    settle_threads(threads);
    check_against_reference({false, false, 101, 67, 900, 1.0f, 0.0f, 5}, 7);
    check_against_reference({true, true, 29, 300, 450, 0.5f, 0.0f, 0}, 8);
    check_against_reference({true, false, 8, 20000, 8, 1.0f, 0.0f, 1}, 9);  // direct, split
  }
}

TEST(Gemm, DegenerateSizes) {
  std::vector<float> C = {1, 2, 3, 4};
  const float A = 5, B = 6;
  gemm<float>(false, false, 2, 2, 0, 1.0f, &A, 1, &B, 2, 0.5f, C.data(), 2);  // K = 0: C *= beta
  EXPECT_EQ(C, (std::vector<float>{0.5f, 1, 1.5f, 2}));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  C = {nan, nan, nan, nan};
  gemm<float>(false, false, 2, 2, 0, 1.0f, &A, 1, &B, 2, 0.0f, C.data(), 2);
  EXPECT_EQ(C, (std::vector<float>{0, 0, 0, 0}));
  gemm<float>(false, false, 0, 2, 3, 1.0f, &A, 1, &B, 2, 0.0f, C.data(), 2);  // nothing to do
  EXPECT_EQ(C, (std::vector<float>{0, 0, 0, 0}));
}

TEST(Gemm, NnaoMlpShapes) {
  // The NNAO MLP's first layer at batch 16: 3844 inputs, 4 units, and its gradients.
  uint64_t seed = 300;
  for (float beta : {0.0f, 1.0f, 0.25f}) {
    const float alpha = beta == 0.25f ? -0.5f : 1.0f;
    check_against_reference({false, true, 16, 4, 3844, alpha, beta}, seed++);
    check_against_reference({false, false, 16, 3844, 4, alpha, beta}, seed++);
    check_against_reference({true, false, 4, 3844, 16, alpha, beta}, seed++);
    check_against_reference({false, true, 16, 1, 4, alpha, beta}, seed++);
    check_against_reference({false, true, 15, 3, 37, alpha, beta, 5}, seed++);
    check_against_reference({true, false, 7, 101, 9, alpha, beta, 3}, seed++);
  }
}

TEST(Gemm, SkinnyShapes) {
  // The U-Net's innermost layers: C with 1-16 columns, a long K or many rows, both thread
  // counts, alpha/beta, padded leading dimensions, a ragged last 64-row block.
  ThreadsGuard guard;
  uint64_t seed = 400;
  for (int threads : {1, 2}) {
    settle_threads(threads);
    for (int64_t N : {1, 3, 4, 5, 16})
      for (float beta : {0.0f, 1.0f, 0.25f}) {
        const float alpha = beta == 0.25f ? -0.5f : 1.0f;
        check_against_reference({true, false, 1000, N, 300, alpha, beta, int64_t(N % 3)}, seed++);
        check_against_reference({false, false, 300, N, 1100, alpha, beta, int64_t(N % 3)}, seed++);
      }
  }
  EXPECT_TRUE(gemm_detail::use_gemm_tn_skinny(true, false, 1000, 16, 300));
  EXPECT_TRUE(gemm_detail::use_gemm_nn_skinny(false, false, 300, 4, 1100));
}

TEST(Gemm, PackedAGivesTheBitsOfGemm) {
  // A packed once and multiplied by several B: bitwise what gemm() gives, with edge
  // micro-panels, several K and MC blocks, both transposes, beta, 1 and 2 threads.
  ThreadsGuard guard;
  Rng rng(31);
  for (int threads : {1, 2}) {
    settle_threads(threads);
    for (bool ta : {false, true})
      for (bool tb : {false, true}) {
        const Case c{ta, tb, 701, 203, 600, 1.0f, 0.5f, 3};
        SCOPED_TRACE(c.str() + " threads=" + std::to_string(threads));
        Problem p = make_problem(c, rng);
        GemmPackedA packed(ta, c.M, c.K, p.A.data(), p.lda, c.N);
        for (int64_t n : {c.N, int64_t(61)}) {  // the typical N and a narrower block
          std::vector<float> want = p.C0, got = p.C0;
          gemm<float>(ta, tb, c.M, n, c.K, 1.0f, p.A.data(), p.lda, p.B.data(), p.ldb, 0.5f, want.data(), p.ldc);
          packed.multiply(tb, n, 1.0f, p.B.data(), p.ldb, 0.5f, got.data(), p.ldc);
          EXPECT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(float)), 0);
        }
      }
  }
}

TEST(Gemm, OneAndTwoThreadsBitwiseEqual) {
  ThreadsGuard guard;
  Rng rng(11);
  // Shapes that split along N, along M, with several K blocks, edge tiles and beta.
  // (The comparison is exact: bitwise.)
  const Case cases[] = {{false, false, 300, 1000, 1000, 1.0f, 0.5f},
                        {false, true, 1000, 40, 777, 1.0f, 1.0f},
                        {true, false, 64, 4096, 64, 1.0f, 0.0f},
                        {true, true, 513, 515, 517, -1.5f, 1.0f, 3},
                        {false, false, 8, 70001, 8, 1.0f, 0.5f},  // the short-K direct path
                        {true, false, 8192, 4, 512, 1.0f, 0.0f},  // skinny paths
                        {false, false, 512, 1, 8192, 1.0f, 1.0f},
                        {false, false, 512, 64, 3000, 1.0f, 0.0f},   // few columns: rows split
                        {false, false, 100, 333, 600, 1.0f, 1.0f}};  // B packed a panel at a time
  for (const Case& c : cases) {
    SCOPED_TRACE(c.str());
    Problem p = make_problem(c, rng);
    std::vector<float> one = run_with_threads(1, c, p), two = run_with_threads(2, c, p);
    EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(float)), 0);
  }
}

TEST(Gemm, LargeProductAgainstVectorProbe) {
  // BLIS's cheap check for sizes the naive reference is too slow for:
  // C*t == beta*C0*t + alpha*A*(B*t) for a random vector t, evaluated in double.
  Rng rng(21);
  for (bool ta : {false, true})
    for (bool tb : {false, true}) {
      const Case c{ta, tb, 1031, 1283, 1537, 0.75f, 0.5f, 2};
      SCOPED_TRACE(c.str());
      Problem p = make_problem(c, rng);
      std::vector<float> C = p.C0;
      gemm<float>(c.ta, c.tb, c.M, c.N, c.K, c.alpha, p.A.data(), p.lda, p.B.data(), p.ldb, c.beta, C.data(), p.ldc);
      std::vector<double> t(size_t(c.N)), bt(size_t(c.K), 0.0), bt_abs(size_t(c.K), 0.0);
      for (auto& x : t) x = rng.normal();
      for (int64_t k = 0; k < c.K; ++k)
        for (int64_t j = 0; j < c.N; ++j) {
          double b = c.tb ? p.B[size_t(j * p.ldb + k)] : p.B[size_t(k * p.ldb + j)];
          bt[size_t(k)] += b * t[size_t(j)];
          bt_abs[size_t(k)] += std::fabs(b * t[size_t(j)]);
        }
      double worst = 0;
      for (int64_t i = 0; i < c.M; ++i) {
        double lhs = 0, rhs = 0, mag = 0;
        for (int64_t j = 0; j < c.N; ++j) {
          lhs += double(C[size_t(i * p.ldc + j)]) * t[size_t(j)];
          rhs += c.beta * double(p.C0[size_t(i * p.ldc + j)]) * t[size_t(j)];
          mag += std::fabs(c.beta * p.C0[size_t(i * p.ldc + j)] * t[size_t(j)]);
        }
        for (int64_t k = 0; k < c.K; ++k) {
          double a = c.ta ? p.A[size_t(k * p.lda + i)] : p.A[size_t(i * p.lda + k)];
          rhs += c.alpha * a * bt[size_t(k)];
          mag += std::fabs(c.alpha * a) * bt_abs[size_t(k)];
        }
        worst = std::max(worst, std::fabs(lhs - rhs) / mag);
      }
      // A float GEMM of depth K has relative error ~ K eps in the worst case, ~sqrt(K) eps
      // typically; a wrong tile or a lost K block gives O(1).
      EXPECT_LT(worst, double(c.K) * FLT_EPSILON) << "worst relative error " << worst;
    }
}

TEST(Gemm, DoubleGenericPathMatchesReference) {
  Rng rng(31);
  for (bool ta : {false, true})
    for (bool tb : {false, true})
      for (double beta : {0.0, 1.0, -0.5}) {
        const int64_t M = 13, N = 9, K = 21, ld = 25;
        std::vector<double> A(size_t(25 * ld)), B(size_t(25 * ld)), C(size_t(M * ld));
        for (auto& x : A) x = rng.normal();
        for (auto& x : B) x = rng.normal();
        for (auto& x : C) x = rng.normal();
        std::vector<double> ref = C;
        if (beta == 0.0) std::fill(C.begin(), C.end(), std::numeric_limits<double>::quiet_NaN());
        gemm<double>(ta, tb, M, N, K, 1.5, A.data(), ld, B.data(), ld, beta, C.data(), ld);
        gemm_reference<double>(ta, tb, M, N, K, 1.5, A.data(), ld, B.data(), ld, beta, ref.data(), ld);
        for (int64_t i = 0; i < M; ++i)
          for (int64_t j = 0; j < N; ++j) EXPECT_NEAR(C[size_t(i * ld + j)], ref[size_t(i * ld + j)], 1e-12);
      }
}
