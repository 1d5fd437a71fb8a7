// bf16 GEMM (Precision::bf16): rounding, every available micro-kernel against an emulated
// reference, the fallback, thread-count independence.
#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "core/kernels/bf16.h"
#include "core/kernels/conv2d.h"
#include "core/kernels/gemm.h"
#include "core/kernels/gemm_pack_bf16.h"
#include "core/kernels/gemm_precision.h"
#include "core/rng.h"
#include "core/thread_pool.h"

using namespace nns;

namespace {

uint16_t bits_of(uint32_t u) { return bf16_bits(std::bit_cast<float>(u)); }

TEST(Bf16Rounding, NearestEvenOnTiesAndNeighbours) {
  EXPECT_EQ(bits_of(0x3f800000u), 0x3f80);  // 1.0 exact
  EXPECT_EQ(bits_of(0x3f808000u), 0x3f80);  // tie, kept bit even: down
  EXPECT_EQ(bits_of(0x3f818000u), 0x3f82);  // tie, kept bit odd: up
  EXPECT_EQ(bits_of(0x3f808001u), 0x3f81);  // just above the tie
  EXPECT_EQ(bits_of(0x3f807fffu), 0x3f80);  // just below
  EXPECT_EQ(bits_of(0xbf818000u), 0xbf82);  // sign does not matter
  EXPECT_EQ(bits_of(0x3fffffffu), 0x4000);  // carries into the exponent
  EXPECT_EQ(bits_of(0x80000000u), 0x8000);  // -0
}

TEST(Bf16Rounding, InfinityOverflowAndNaN) {
  EXPECT_EQ(bits_of(0x7f800000u), 0x7f80);
  EXPECT_EQ(bits_of(0xff800000u), 0xff80);
  EXPECT_EQ(bits_of(0x7f7fffffu), 0x7f80);  // FLT_MAX is past the largest bf16: infinity
  EXPECT_EQ(bits_of(0x7f7f7fffu), 0x7f7f);  // largest finite bf16 stays
  // NaNs stay NaNs, including those whose payload is only in the dropped half (the
  // plain rounding formula would carry them into infinity).
  for (uint32_t nan : {0x7f800001u, 0x7fc00000u, 0xff800001u, 0x7fffffffu, 0x7f80ffffu}) {
    const float back = bf16_to_float(bits_of(nan));
    EXPECT_TRUE(std::isnan(back)) << std::hex << nan;
    EXPECT_EQ(std::signbit(back), bool(nan >> 31)) << std::hex << nan;
  }
}

TEST(Bf16Rounding, Denormals) {
  EXPECT_EQ(bits_of(0x00000001u), 0x0000);  // far below half the smallest bf16 denormal
  EXPECT_EQ(bits_of(0x00008000u), 0x0000);  // tie to even (zero)
  EXPECT_EQ(bits_of(0x00018000u), 0x0002);  // tie to even (up)
  EXPECT_EQ(bits_of(0x00010000u), 0x0001);  // smallest bf16 denormal, exact
  EXPECT_EQ(bits_of(0x007fffffu), 0x0080);  // largest fp32 denormal rounds to FLT_MIN
  EXPECT_EQ(bits_of(0x80018000u), 0x8002);
}

TEST(Bf16Rounding, VectorPackingGivesTheScalarBits) {
  if (!cpu_features().avx512f) GTEST_SKIP() << "no AVX-512F on this CPU: only the scalar path runs";
  Rng rng(7);
  for (int W : {14, 32, 4, 16}) {
    for (int64_t kc : {1, 2, 7, 64}) {
      std::vector<float> src(size_t(kc * W));
      for (size_t i = 0; i < src.size(); ++i) {
        // Random bit patterns: every class (NaN, infinity, denormal, ties) turns up.
        const uint32_t u = uint32_t(rng.next_u64() >> 32);
        src[i] = std::bit_cast<float>(i % 5 == 0 ? (u & 0xffff8000u) | 0x8000u : u);
      }
      const size_t words = size_t((kc + 1) / 2 * W);
      std::vector<uint32_t> vec(words, 0xdeadbeefu), sca(words, 0xdeadbeefu);
      bf16_detail::pair_bf16_avx512(vec.data(), src.data(), W, kc);
      bf16_detail::pair_bf16_scalar(sca.data(), src.data(), W, kc);
      EXPECT_EQ(vec, sca) << "W=" << W << " kc=" << kc;
      // round_copy_bf16 (vector rows with a masked tail) against round_to_bf16.
      std::vector<float> rounded(src.size());
      round_copy_bf16(rounded.data(), src.data(), kc, W, W);
      for (size_t i = 0; i < src.size(); ++i)
        ASSERT_EQ(std::bit_cast<uint32_t>(rounded[i]), std::bit_cast<uint32_t>(round_to_bf16(src[i])))
            << std::hex << std::bit_cast<uint32_t>(src[i]);
    }
  }
}

// The kernels to test on this machine: the generic one always, AVX512-BF16 where the CPU
// has it. Each run sets force_generic_bf16 accordingly (and restores it).
std::vector<Bf16Isa> available_isas() {
  std::vector<Bf16Isa> isas{Bf16Isa::generic};
  if (cpu_features().avx512_bf16) isas.push_back(Bf16Isa::avx512_bf16);
  return isas;
}

class IsaGuard {
 public:
  explicit IsaGuard(Bf16Isa isa) { force_generic_bf16(isa == Bf16Isa::generic); }
  ~IsaGuard() { force_generic_bf16(false); }
};

const char* isa_name(Bf16Isa isa) { return isa == Bf16Isa::generic ? "generic" : "avx512_bf16"; }

// Random bit patterns: every class (NaN, infinity, denormal, ties) turns up.
std::vector<float> random_bits(size_t n, Rng& rng) {
  std::vector<float> v(n);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t u = uint32_t(rng.next_u64() >> 32);
    v[i] = std::bit_cast<float>(i % 5 == 0 ? (u & 0xffff8000u) | 0x8000u : u);
  }
  return v;
}

// The packers that write bf16 pairs directly (gemm_pack_bf16.h) against the fp32 packers
// followed by pair_bf16: the same words, nothing written past the panels. Both
// transposes, edge panels (fewer rows or columns than a panel), odd kc (a zero high half),
// kc across the 32-step blocks of the transposing path, unaligned starts.
TEST(Bf16Packing, DirectPackersGiveThePairedWords) {
  using namespace gemm_detail;
  Rng rng(11);
  const int64_t ld = 213, rows = 150;
  const std::vector<float> src = random_bits(size_t(ld * rows), rng);
  constexpr uint32_t kSentinel = 0xdeadbeefu;
  for (Bf16Isa isa : available_isas())  // the generic kernel's packers: pack, then pair
    for (bool trans : {false, true})
      for (int64_t extent : {1, 5, 14, 15, 16, 17, 29, 32, 33, 70})
        for (int64_t kc : {1, 2, 3, 16, 31, 32, 33, 64, 67}) {
          IsaGuard guard(isa);
          SCOPED_TRACE(std::string(isa_name(isa)) + " trans=" + std::to_string(trans) +
                       " extent=" + std::to_string(extent) + " kc=" + std::to_string(kc));
          // op(X) of extent x kc (A) or kc x extent (B) starting at row 3, column 5 of op(X).
          const MatView view{src.data(), ld, trans};
          const int64_t kp = (kc + 1) / 2;
          auto check = [&](int W, auto pack_fp32, auto pack_bf16) {
            const int64_t panels = (extent + W - 1) / W;
            std::vector<float> fp32(size_t(panels * kc * W));
            pack_fp32(fp32.data());
            std::vector<uint32_t> want(size_t(panels * kp * W) + 16, kSentinel), got = want;
            pair_panels_bf16_to(want.data(), fp32.data(), W, extent, kc);
            pack_bf16(got.data());
            EXPECT_EQ(want, got) << "W=" << W;
          };
          check(
              kMR, [&](float* d) { pack_a<kMR>(d, view, 3, extent, 5, kc); },
              [&](uint32_t* d) { pack_a_bf16<kMR>(d, view, 3, extent, 5, kc); });
          check(
              kNR, [&](float* d) { pack_b<kNR>(d, view, 3, kc, 5, extent); },
              [&](uint32_t* d) { pack_b_bf16<kNR>(d, view, 3, kc, 5, extent); });
        }
}

// An implicit convolution's column panels (conv2d_implicit.h) packed straight into bf16
// pairs: the words of its fp32 panels paired, for panels inside one output row and
// panels straddling rows (W_out not a multiple of the panel width), a partial last
// panel, odd and even kc, a K window that starts inside the column matrix.
TEST(Bf16Packing, ImplicitColumnsGiveThePairedWords) {
  using namespace gemm_detail;
  Rng rng(12);
  for (Bf16Isa isa : available_isas())
    for (int64_t W : {kNR * 2, kNR + 7}) {
      IsaGuard guard(isa);
      const ConvGeometry g = conv2d_geometry(1, 3, 6, W, 4, 3, 3, 1, 1, 1, 1, 1, 1, 1);
      const std::vector<float> image = random_bits(size_t(g.C_in * g.H * g.W), rng);
      const PaddedRows layout = PaddedRows::layout(g, implicit_input_rows(g, g.H_out));
      std::vector<float> rows(size_t(layout.chan * g.C_in));
      layout.fill(rows.data(), image.data(), g, -g.pad_h);
      const std::vector<int64_t> k_off = ImplicitColumns::k_offsets(g, layout);
      const ImplicitColumns cols(g, layout, rows.data(), k_off);
      const int64_t N = g.H_out * g.W_out;
      for (auto [pc, kc] : {std::pair<int64_t, int64_t>{0, g.col_rows()}, {1, 20}, {4, 1}})
        for (auto [jc, nc] : {std::pair<int64_t, int64_t>{0, N}, {5, N - 5 - 3}}) {
          SCOPED_TRACE(std::string(isa_name(isa)) + " W=" + std::to_string(W) + " pc=" + std::to_string(pc) +
                       " kc=" + std::to_string(kc) + " jc=" + std::to_string(jc));
          const int64_t panels = (nc + kNR - 1) / kNR, kp = (kc + 1) / 2;
          // The packers store whole aligned panels (as into gemm_packed.h's buffers).
          auto aligned = [](size_t words) { return std::aligned_alloc(64, (words * 4 + 63) / 64 * 64 + 64); };
          float* f = static_cast<float*>(aligned(size_t(panels * kc * kNR)));
          cols(f, pc, kc, jc, nc);
          std::vector<uint32_t> want(size_t(panels * kp * kNR));
          pair_panels_bf16_to(want.data(), f, kNR, nc, kc);
          std::free(f);
          uint32_t* got = static_cast<uint32_t*>(aligned(want.size()));
          std::fill(got, got + want.size() + 16, 0xdeadbeefu);
          cols(got, pc, kc, jc, nc);
          EXPECT_EQ(std::vector<uint32_t>(got, got + want.size()), want);
          EXPECT_EQ(got[want.size()], 0xdeadbeefu);  // nothing written past the panels
          std::free(got);
        }
    }
}

struct Case {
  bool ta, tb;
  int64_t M, N, K;
  float alpha, beta;
  std::string str() const {
    return "ta=" + std::to_string(ta) + " tb=" + std::to_string(tb) + " M=" + std::to_string(M) +
           " N=" + std::to_string(N) + " K=" + std::to_string(K) + " alpha=" + std::to_string(alpha) +
           " beta=" + std::to_string(beta);
  }
};

struct Problem {
  std::vector<float> A, B, C0;
  int64_t lda, ldb, ldc;
};

Problem make_problem(const Case& c, Rng& rng) {
  Problem p;
  const int64_t arows = c.ta ? c.K : c.M, brows = c.tb ? c.N : c.K;
  p.lda = (c.ta ? c.M : c.K) + 3;  // padded leading dimensions
  p.ldb = (c.tb ? c.K : c.N) + 1;
  p.ldc = c.N + 2;
  auto fill = [&](std::vector<float>& v, size_t n) {
    v.resize(n);
    for (auto& x : v) x = float(rng.normal());
  };
  fill(p.A, size_t(arows * p.lda));
  fill(p.B, size_t(brows * p.ldb));
  fill(p.C0, size_t(c.M * p.ldc));
  return p;
}

std::vector<float> run(const Case& c, const Problem& p) {
  ScopedGemmPrecision bf16(Precision::bf16);
  std::vector<float> C = p.C0;
  if (c.beta == 0.0f) std::fill(C.begin(), C.end(), std::numeric_limits<float>::quiet_NaN());
  gemm<float>(c.ta, c.tb, c.M, c.N, c.K, c.alpha, p.A.data(), p.lda, p.B.data(), p.ldb, c.beta, C.data(), p.ldc);
  return C;
}

// The emulated bf16 product: inputs rounded to bf16 (RNE), products exact in double (a
// product of two bf16 has 16 significant bits), sums in double. A kernel sums the K
// products in fp32: at most one rounding per product (vdpbf16ps adds the two products of
// a pair to the accumulator one at a time; the generic kernel adds their exact sum),
// one per K block of <= 256 when the block's sum is added to C, and at most three for
// alpha, beta and the final sum. So with u = 2^-24 and n = K + 2 ceil(K / 256) + 3,
//   |C - C_ref| <= n u / (1 - n u) * (|alpha| sum_k |a_ik b_kj| + |beta C0_ij|)
//                  + K 2^-126 |alpha|  (vdpbf16ps flushes denormal products to zero;
//                  the random normal inputs here give none, so this term is slack).
// Unrounded fp32 inputs miss this bound on the short-K cases (their products differ by
// ~2^-9 relative) but can pass it at K = 3844; InputsAreRoundedToBf16 checks the rounding
// exactly on every path.
void check(const Case& c, uint64_t seed) {
  SCOPED_TRACE(c.str());
  Rng rng(seed);
  Problem p = make_problem(c, rng);
  const std::vector<float> C = run(c, p);
  auto at_a = [&](int64_t i, int64_t k) {
    return double(round_to_bf16(c.ta ? p.A[size_t(k * p.lda + i)] : p.A[size_t(i * p.lda + k)]));
  };
  auto at_b = [&](int64_t k, int64_t j) {
    return double(round_to_bf16(c.tb ? p.B[size_t(j * p.ldb + k)] : p.B[size_t(k * p.ldb + j)]));
  };
  const double n = double(c.K + 2 * ((c.K + 255) / 256) + 3), u = std::ldexp(1.0, -24);
  const double gamma = n * u / (1 - n * u);
  int bad = 0;
  for (int64_t i = 0; i < c.M; ++i)
    for (int64_t j = 0; j < c.N; ++j) {
      double sum = 0, mag = 0;
      for (int64_t k = 0; k < c.K; ++k) {
        const double prod = at_a(i, k) * at_b(k, j);
        sum += prod;
        mag += std::fabs(prod);
      }
      const size_t at = size_t(i * p.ldc + j);
      const double c0 = c.beta == 0.0f ? 0.0 : double(p.C0[at]);
      const double ref = double(c.alpha) * sum + double(c.beta) * c0;
      const double bound = gamma * (std::fabs(c.alpha) * mag + std::fabs(c.beta * c0)) +
                           double(c.K) * std::ldexp(1.0, -126) * std::fabs(c.alpha);
      if (!(std::fabs(C[at] - ref) <= bound) && bad++ < 5)
        ADD_FAILURE() << "C[" << i << "," << j << "] = " << C[at] << ", reference " << ref << ", bound " << bound;
    }
  // The padding columns of C: the fp32 kernels' store, tested in test_gemm.cpp.
  EXPECT_EQ(bad, 0);
}

// Packed shapes: edge tiles, odd K (a half-empty last pair), several K blocks, more rows
// than one MC block (B packed a block at a time); unpacked shapes: the NNAO MLP's tiny
// products and a few columns of C (skinny paths).
const std::vector<Case> kCases = {
    {false, false, 64, 64, 64, 1.0f, 0.0f},  {false, false, 15, 33, 17, 1.0f, 1.0f},
    {true, false, 29, 47, 300, 0.5f, 0.25f}, {false, true, 100, 70, 513, 1.0f, 1.0f},
    {true, true, 37, 65, 129, -2.0f, 0.0f},  {false, false, 400, 40, 50, 1.0f, 0.5f},
    {false, true, 16, 4, 3844, 1.0f, 0.0f},  {true, false, 4, 3844, 16, 1.0f, 1.0f},
    {false, false, 200, 3, 500, 1.0f, 0.0f}, {true, false, 300, 8, 200, 1.0f, 1.0f},
};

TEST(GemmBf16, EachKernelMatchesEmulatedReference) {
  for (Bf16Isa isa : available_isas()) {
    IsaGuard guard(isa);
    ASSERT_EQ(bf16_isa(), isa);
    SCOPED_TRACE(isa_name(isa));
    for (size_t i = 0; i < kCases.size(); ++i) check(kCases[i], 100 + i);
  }
}

// Inputs 1 + 3 * 2^-9 round to bf16 1 + 2^-7: every product of them with 1 is exactly
// 1.0078125 and the K = 64 sum 64.5 (exact in fp32); fp32 inputs would give 64.375.
TEST(GemmBf16, InputsAreRoundedToBf16) {
  for (Bf16Isa isa : available_isas()) {
    IsaGuard guard(isa);
    for (auto [M, N] : {std::pair<int64_t, int64_t>{40, 48}, {16, 2}, {3, 5}}) {
      SCOPED_TRACE(std::string(isa_name(isa)) + " M=" + std::to_string(M) + " N=" + std::to_string(N));
      const int64_t K = 64;
      std::vector<float> A(size_t(M * K), 1.0f + 3.0f / 512.0f), B(size_t(K * N), 1.0f);
      std::vector<float> C(size_t(M * N), -1.0f);
      {
        ScopedGemmPrecision bf16(Precision::bf16);
        gemm<float>(false, false, M, N, K, 1.0f, A.data(), K, B.data(), N, 0.0f, C.data(), N);
      }
      for (float x : C) ASSERT_EQ(x, 64.5f);
      gemm<float>(false, false, M, N, K, 1.0f, A.data(), K, B.data(), N, 0.0f, C.data(), N);
      for (float x : C) ASSERT_NEAR(x, 64.375f, 1e-4f) << "fp32 is the default";
    }
  }
}

TEST(GemmBf16, DispatchSaysWhatRunsAndFallsBackWhenForced) {
  EXPECT_EQ(gemm_precision(), Precision::fp32);
  if (cpu_features().avx512_bf16) {
    EXPECT_EQ(bf16_isa(), Bf16Isa::avx512_bf16);
    EXPECT_EQ(bf16_isa_description().rfind("avx512_bf16", 0), 0u) << bf16_isa_description();
  } else {
    EXPECT_EQ(bf16_isa(), Bf16Isa::generic);
    EXPECT_NE(bf16_isa_description().find("no AVX512-BF16"), std::string::npos);
  }
  {
    IsaGuard guard(Bf16Isa::generic);
    EXPECT_EQ(bf16_isa(), Bf16Isa::generic);
    EXPECT_NE(bf16_isa_description().find("fell back"), std::string::npos) << bf16_isa_description();
  }
  std::printf("bf16 GEMM on this machine: %s\n", bf16_isa_description().c_str());
}

TEST(GemmBf16, OneAndTwoThreadsBitwiseEqual) {
  const int saved = num_threads();
  for (Bf16Isa isa : available_isas()) {
    IsaGuard guard(isa);
    for (const Case& c : std::vector<Case>{{false, false, 300, 500, 300, 1.0f, 1.0f},
                                           {true, false, 64, 2000, 700, 1.0f, 0.0f},
                                           {false, true, 700, 64, 600, 1.0f, 1.0f},
                                           {false, false, 512, 4, 2048, 1.0f, 1.0f}}) {
      SCOPED_TRACE(std::string(isa_name(isa)) + " " + c.str());
      Rng rng(3);
      const Problem p = make_problem(c, rng);
      set_num_threads(1);
      const std::vector<float> one = run(c, p);
      set_num_threads(2);
      const std::vector<float> two = run(c, p);
      EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(float)), 0);
    }
  }
  set_num_threads(saved);
}

// Weights packed once (GemmPackedA) in bf16 keep only their bf16 panels, converted when
// packed: bitwise the product gemm() gives in bf16 (which packs them per call),
// with edge panels, several K and MC blocks, an odd last K block, both transposes, a
// narrower B and B given only through a packer (of bf16 pairs, or of fp32 panels that the
// loops pair), on 1 and 2 threads.
TEST(GemmBf16, PackedAGivesTheBitsOfGemm) {
  const int saved = num_threads();
  for (Bf16Isa isa : available_isas()) {
    IsaGuard guard(isa);
    for (int threads : {1, 2}) {
      set_num_threads(threads);
      for (bool ta : {false, true})
        for (bool tb : {false, true}) {
          const Case c{ta, tb, 701, 203, 601, 1.0f, 0.5f};
          SCOPED_TRACE(std::string(isa_name(isa)) + " " + c.str() + " threads=" + std::to_string(threads));
          Rng rng(41);
          const Problem p = make_problem(c, rng);
          const ScopedGemmPrecision bf16(Precision::bf16);
          const GemmPackedA packed(ta, c.M, c.K, p.A.data(), p.lda, c.N);
          ASSERT_TRUE(packed.packs_for(c.N));
          for (int64_t n : {c.N, int64_t(61)}) {
            std::vector<float> want = p.C0, got = p.C0, through_packer = p.C0, through_fp32_packer = p.C0;
            gemm<float>(ta, tb, c.M, n, c.K, 1.0f, p.A.data(), p.lda, p.B.data(), p.ldb, 0.5f, want.data(), p.ldc);
            packed.multiply(tb, n, 1.0f, p.B.data(), p.ldb, 0.5f, got.data(), p.ldc);
            const auto packer = gemm_detail::packer_b(gemm_detail::MatView{p.B.data(), p.ldb, tb});
            packed.multiply_packing_b(n, 1.0f, packer, 0.5f, through_packer.data(), p.ldc);
            // A packer of fp32 panels only: gemm_packed_loops pairs them itself.
            packed.multiply_packing_b(
                n, 1.0f,
                [&](float* dst, int64_t pc, int64_t kc, int64_t jc, int64_t nc) { packer(dst, pc, kc, jc, nc); }, 0.5f,
                through_fp32_packer.data(), p.ldc);
            EXPECT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(float)), 0);
            EXPECT_EQ(std::memcmp(want.data(), through_packer.data(), want.size() * sizeof(float)), 0);
            EXPECT_EQ(std::memcmp(want.data(), through_fp32_packer.data(), want.size() * sizeof(float)), 0);
          }
        }
    }
  }
  set_num_threads(saved);
}

// The skinny shapes (a few columns of C, a long A) round A as they load it instead of
// through a copy: bitwise the fp32 product of the bf16-rounded operands on the same path.
TEST(GemmBf16, SkinnyPathsGiveTheBitsOfRoundedOperands) {
  const int saved = num_threads();
  for (const Case& c : std::vector<Case>{{false, false, 300, 4, 1100, 1.0f, 0.0f},
                                         {false, false, 37, 1, 700, -0.5f, 1.0f},
                                         {true, false, 1000, 16, 300, 1.0f, 0.5f},
                                         {true, false, 333, 3, 17, 2.0f, 0.0f}}) {
    ASSERT_TRUE(gemm_detail::use_gemm_nn_skinny(c.ta, c.tb, c.M, c.N, c.K) ||
                gemm_detail::use_gemm_tn_skinny(c.ta, c.tb, c.M, c.N, c.K));
    Rng rng(43);
    Problem p = make_problem(c, rng);
    // Ties, denormals and NaN among the inputs, so a rounding that differs shows.
    p.A[1] = std::bit_cast<float>(0x3f818000u);
    p.A[2] = std::bit_cast<float>(0x007fffffu);
    p.A[size_t(p.lda)] = std::bit_cast<float>(0x3f808000u);
    Problem rounded = p;
    for (auto& x : rounded.A) x = round_to_bf16(x);
    for (auto& x : rounded.B) x = round_to_bf16(x);
    for (int threads : {1, 2}) {
      set_num_threads(threads);
      SCOPED_TRACE(c.str() + " threads=" + std::to_string(threads));
      std::vector<float> want = p.C0;  // as run() starts it: C's padding columns compare too
      if (c.beta == 0.0f) std::fill(want.begin(), want.end(), std::numeric_limits<float>::quiet_NaN());
      gemm<float>(c.ta, c.tb, c.M, c.N, c.K, c.alpha, rounded.A.data(), p.lda, rounded.B.data(), p.ldb, c.beta,
                  want.data(), p.ldc);
      const std::vector<float> got = run(c, p);
      EXPECT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(float)), 0);
    }
  }
  set_num_threads(saved);
}

}  // namespace
