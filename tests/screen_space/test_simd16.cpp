// Every operation of the simd16 backend this build uses (screen_space/simd16.h: AVX-512,
// AVX2 or generic), lane by lane against scalar code, over the floats where instruction
// sets disagree: NaN, +-inf, -0, subnormals, values at and past the int range, halves
// for rounding, random bit patterns; masks with holes and with bits above lane 15.
// A wrong intrinsic (an operand order, a rounding mode, a compare predicate, a lane
// half swapped) fails here, whichever backend the build takes.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <bit>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "data/view.h"
#include "screen_space/simd16.h"

using namespace nns::screen_space::simd;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
const float kNaN = std::numeric_limits<float>::quiet_NaN();

// The floats where implementations part ways.
std::vector<float> special_floats() {
  return {0.0f,
          -0.0f,
          1.0f,
          -1.0f,
          0.5f,
          -0.5f,
          1.5f,
          -1.5f,
          2.5f,
          -2.5f,
          0.49999997f,
          -0.49999997f,
          0.99999994f,
          -0.99999994f,
          3.0e-39f /* subnormal */,
          -3.0e-39f,
          FLT_MIN,
          -FLT_MIN,
          std::numeric_limits<float>::denorm_min(),
          -std::numeric_limits<float>::denorm_min(),
          FLT_MAX,
          -FLT_MAX,
          kInf,
          -kInf,
          kNaN,
          -kNaN,
          std::bit_cast<float>(0x7FA00001u) /* signalling NaN */,
          2147483648.0f /* 2^31 */,
          -2147483648.0f,
          2147483520.0f /* largest below 2^31 */,
          -2147483904.0f /* next below -2^31 */,
          8388607.5f,
          -8388607.5f,
          16777216.0f,
          1e10f,
          -1e10f,
          1e30f /* data::kSkyDepth */,
          -87.0f,
          -87.5f,
          88.0f,
          3.14159265f,
          -0.1f,
          1e-7f,
          100.25f};
}

// A float equal to the reference: the same bits, or NaN for NaN (payloads are the
// hardware's business; -0 against +0 is not).
bool same(float a, float b) {
  return std::isnan(a) ? std::isnan(b) : std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
}

struct Floats {
  alignas(64) float v[kLanes];
};
Floats out(VF a) {
  Floats f;
  store(f.v, a, kAll);
  return f;
}
struct Ints {
  alignas(64) int32_t v[kLanes];
};
Ints out(VI a) {
  // A VI reaches memory only through a float store of its bits here: the backend has no
  // integer store, and to_float would round.
  Ints r;
  const VF bits = [&] {
    VF f = splat(0.0f);
    static_assert(sizeof(VF) == sizeof(VI));
    std::memcpy(&f, &a, sizeof f);
    return f;
  }();
  const Floats f = out(bits);
  std::memcpy(r.v, f.v, sizeof r.v);
  return r;
}

// Inputs as blocks of 16: every pair of specials (a in one stream, b in the other) and
// random bit patterns (every exponent, so NaNs, infinities and subnormals among them).
struct Pairs {
  std::vector<float> a, b;
};
Pairs float_pairs(uint32_t seed) {
  const auto s = special_floats();
  Pairs p;
  for (float x : s)
    for (float y : s) p.a.push_back(x), p.b.push_back(y);
  std::mt19937 rng(seed);
  for (int i = 0; i < 16 * 2000; ++i) {
    p.a.push_back(std::bit_cast<float>(uint32_t(rng())));
    p.b.push_back(i % 3 == 0 ? s[rng() % s.size()] : std::bit_cast<float>(uint32_t(rng())));
  }
  while (p.a.size() % kLanes) p.a.push_back(1.0f), p.b.push_back(-1.0f);
  return p;
}

// Masks with holes, runs across the two 8-lane halves, and bits above lane 15 (ignored).
std::vector<Mask> masks(uint32_t seed) {
  std::vector<Mask> m = {0u,      kAll,    1u,      0x8000u, 0x00FFu,     0xFF00u,     0x5555u,  0xAAAAu, 0x0180u,
                         0x7FFEu, 0x8001u, 0x0100u, 0x0080u, 0xFFFF0000u, 0xFFFFFFFFu, 0x12345u, 0xF00Fu};
  std::mt19937 rng(seed);
  for (int i = 0; i < 200; ++i) m.push_back(uint32_t(rng()));
  return m;
}

template <class Vector, class Scalar>
void expect_binary(const Pairs& p, Vector vec, Scalar ref, const char* what) {
  for (size_t i = 0; i < p.a.size(); i += kLanes) {
    const Floats r = out(vec(load(&p.a[i]), load(&p.b[i])));
    for (int l = 0; l < kLanes; ++l) {
      const float want = ref(p.a[i + l], p.b[i + l]);
      ASSERT_TRUE(same(r.v[l], want)) << what << " lane " << l << " (" << p.a[i + l] << ", " << p.b[i + l] << "): got "
                                      << r.v[l] << ", scalar " << want;
    }
  }
}

template <class Vector, class Scalar>
void expect_unary(const Pairs& p, Vector vec, Scalar ref, const char* what) {
  expect_binary(
      p, [&](VF a, VF) { return vec(a); }, [&](float a, float) { return ref(a); }, what);
}

// The x86 conversion's answer where C++'s int(float) is undefined: INT_MIN.
int32_t truncate_or_int_min(float x) {
  return std::isnan(x) || x >= 2147483648.0f || x < -2147483648.0f ? INT32_MIN : int32_t(x);
}

TEST(Simd16, ReportsItsBackend) {
  std::printf("simd16 backend: %s\n", kBackend);
  SUCCEED();
}

TEST(Simd16, ArithmeticMatchesScalarLaneByLane) {
  const Pairs p = float_pairs(1);
  expect_binary(
      p, [](VF a, VF b) { return a + b; }, [](float a, float b) { return a + b; }, "+");
  expect_binary(
      p, [](VF a, VF b) { return a - b; }, [](float a, float b) { return a - b; }, "-");
  expect_binary(
      p, [](VF a, VF b) { return a * b; }, [](float a, float b) { return a * b; }, "*");
  expect_binary(
      p, [](VF a, VF b) { return a / b; }, [](float a, float b) { return a / b; }, "/");
  expect_unary(
      p, [](VF a) { return sqrt(a); }, [](float a) { return std::sqrt(a); }, "sqrt");
  expect_unary(
      p, [](VF a) { return -a; }, [](float a) { return 0.0f - a; }, "unary -");
  expect_unary(
      p, [](VF a) { return abs(a); }, [](float a) { return std::fabs(a); }, "abs");
}

TEST(Simd16, MinMaxTakeTheScalarOperandOnNaNAndSignedZero) {
  // min(a, b) is b < a ? b : a: a NaN in a stays, a NaN in b gives a, min(-0, +0) is -0.
  const Pairs p = float_pairs(2);
  expect_binary(
      p, [](VF a, VF b) { return min(a, b); }, [](float a, float b) { return b < a ? b : a; }, "min");
  expect_binary(
      p, [](VF a, VF b) { return max(a, b); }, [](float a, float b) { return b > a ? b : a; }, "max");
  expect_unary(
      p, [](VF a) { return saturate(a); },
      [](float a) {
        const float t = 0.0f > a ? 0.0f : a;
        return 1.0f < t ? 1.0f : t;
      },
      "saturate");
}

TEST(Simd16, RoundingAndConversionsMatchScalar) {
  const Pairs p = float_pairs(3);
  expect_unary(
      p, [](VF a) { return floor(a); }, [](float a) { return std::floor(a); }, "floor");
  for (size_t i = 0; i < p.a.size(); i += kLanes) {
    const VF a = load(&p.a[i]);
    const Ints t = out(to_int(a)), f = out(floor_to_int(a));
    for (int l = 0; l < kLanes; ++l) {
      const float x = p.a[i + l];
      ASSERT_EQ(t.v[l], truncate_or_int_min(x)) << "to_int(" << x << ")";
      ASSERT_EQ(f.v[l], truncate_or_int_min(std::floor(x))) << "floor_to_int(" << x << ")";
    }
  }
}

TEST(Simd16, IntegerLanesMatchScalar) {
  std::vector<int32_t> v = {
      0,     1,      -1,    2,        -2,        7,       INT32_MAX, INT32_MIN, INT32_MAX - 1, INT32_MIN + 1,
      46341, -46341, 65536, 16777217, -16777217, 1 << 30, 123456789, -987654321};
  std::mt19937 rng(4);
  for (int i = 0; i < 16 * 500; ++i) v.push_back(int32_t(rng()));
  while (v.size() % kLanes) v.push_back(3);
  const std::vector<std::pair<int, int>> bounds = {{0, 319}, {0, 0},          {-5, 5},       {INT32_MIN, INT32_MAX},
                                                   {7, 7},   {INT32_MIN, -1}, {1, INT32_MAX}};
  for (size_t i = 0; i < v.size(); i += kLanes) {
    // Lanes from v through the float view of their bits (the backend loads floats).
    float a_bits[kLanes], b_bits[kLanes];
    for (int l = 0; l < kLanes; ++l)
      a_bits[l] = std::bit_cast<float>(v[i + size_t(l)]),
      b_bits[l] = std::bit_cast<float>(v[(i + size_t(l) * 7 + 5) % v.size()]);
    VI a, b;
    {
      const VF fa = load(a_bits), fb = load(b_bits);
      std::memcpy(&a, &fa, sizeof a), std::memcpy(&b, &fb, sizeof b);
    }
    const Ints sum = out(a + b), prod = out(a * b), lanes = out(a + lane_index());
    const Ints sp = out(splat_i(v[i]));
    const Floats asf = out(to_float(a));
    for (int l = 0; l < kLanes; ++l) {
      const uint32_t x = std::bit_cast<uint32_t>(a_bits[l]), y = std::bit_cast<uint32_t>(b_bits[l]);
      ASSERT_EQ(uint32_t(sum.v[l]), x + y) << "VI + lane " << l;  // wraps, as the hardware does
      ASSERT_EQ(uint32_t(prod.v[l]), x * y) << "VI * lane " << l;
      ASSERT_EQ(uint32_t(lanes.v[l]), x + uint32_t(l)) << "lane_index lane " << l;
      ASSERT_TRUE(same(asf.v[l], float(int32_t(x)))) << "to_float(" << int32_t(x) << ")";
      ASSERT_EQ(sp.v[l], v[i]) << "splat_i";
    }
    for (auto [lo, hi] : bounds) {
      const Ints c = out(clamp(a, lo, hi));
      for (int l = 0; l < kLanes; ++l) {
        const int32_t x = int32_t(std::bit_cast<uint32_t>(a_bits[l]));
        ASSERT_EQ(c.v[l], x < lo ? lo : (x > hi ? hi : x)) << "clamp(" << x << ", " << lo << ", " << hi << ")";
      }
    }
  }
}

TEST(Simd16, ComparesGiveTheScalarBitsAndSelectBlendsByThem) {
  const Pairs p = float_pairs(5);
  const std::vector<Mask> ms = masks(5);
  for (size_t i = 0; i < p.a.size(); i += kLanes) {
    const VF a = load(&p.a[i]), b = load(&p.b[i]);
    Mask want_lt = 0, want_le = 0, want_gt = 0, want_ge = 0, want_sky = 0;
    for (int l = 0; l < kLanes; ++l) {
      const float x = p.a[i + l], y = p.b[i + l];
      want_lt |= Mask(x < y) << l, want_le |= Mask(x <= y) << l;
      want_gt |= Mask(x > y) << l, want_ge |= Mask(x >= y) << l;
      want_sky |= Mask(nns::data::is_sky(x)) << l;
    }
    ASSERT_EQ(lt(a, b), want_lt) << "lt at " << i;
    ASSERT_EQ(le(a, b), want_le) << "le at " << i;
    ASSERT_EQ(gt(a, b), want_gt) << "gt at " << i;
    ASSERT_EQ(ge(a, b), want_ge) << "ge at " << i;
    ASSERT_EQ(sky(a), want_sky) << "sky at " << i;
    const Mask m = ms[(i / kLanes) % ms.size()];
    const Floats s = out(select(m, a, b));
    for (int l = 0; l < kLanes; ++l)
      ASSERT_TRUE(same(s.v[l], (m >> l & 1) ? p.a[i + l] : p.b[i + l])) << "select mask " << m << " lane " << l;
  }
  const Floats sp = out(splat(-0.0f));
  for (int l = 0; l < kLanes; ++l) EXPECT_TRUE(same(sp.v[l], -0.0f));
}

TEST(Simd16, Scale2IsLdexpAlsoForSubnormalAndOverflowingResults) {
  // Every integral n that moves a float across the whole range, both ways; a from the
  // specials and random bit patterns (subnormal a included).
  std::vector<float> ns;
  for (int n = -320; n <= 320; ++n) ns.push_back(float(n));
  ns.push_back(-0.0f);
  Pairs p;
  std::mt19937 rng(6);
  const auto s = special_floats();
  for (float n : ns) {
    for (float a : s) p.a.push_back(a), p.b.push_back(n);
    for (int k = 0; k < 48; ++k) p.a.push_back(std::bit_cast<float>(uint32_t(rng()))), p.b.push_back(n);
  }
  while (p.a.size() % kLanes) p.a.push_back(1.0f), p.b.push_back(0.0f);
  expect_binary(
      p, [](VF a, VF n) { return scale2(a, n); }, [](float a, float n) { return std::ldexp(a, int(n)); }, "scale2");
}

TEST(Simd16, Scale2NormalIsLdexpForExponentsOfNormalPowers) {
  // n over [-126, 127], where 2^n is a normal float: one multiply, also to a subnormal
  // or an overflowing result; a from the specials and random bit patterns.
  Pairs p;
  std::mt19937 rng(7);
  const auto s = special_floats();
  for (int n = -126; n <= 127; ++n) {
    for (float a : s) p.a.push_back(a), p.b.push_back(float(n));
    for (int k = 0; k < 48; ++k) p.a.push_back(std::bit_cast<float>(uint32_t(rng()))), p.b.push_back(float(n));
  }
  while (p.a.size() % kLanes) p.a.push_back(1.0f), p.b.push_back(0.0f);
  expect_binary(
      p, [](VF a, VF n) { return scale2_normal(a, n); }, [](float a, float n) { return std::ldexp(a, int(n)); },
      "scale2_normal");
}

TEST(Simd16, PreluPicksByTheSignOfX) {
  const Pairs p = float_pairs(7);
  for (size_t i = 0; i < p.a.size(); i += kLanes) {
    const size_t j = (i + 5 * kLanes) % p.a.size();
    const VF x = load(&p.a[i]), alpha = load(&p.b[i]), beta = load(&p.b[j]);
    const Floats r = out(prelu(x, alpha, beta));
    for (int l = 0; l < kLanes; ++l) {
      const float xv = p.a[i + l], want = xv > 0 ? p.b[j + l] * xv : p.b[i + l] * xv;
      ASSERT_TRUE(same(r.v[l], want)) << "prelu(" << xv << ") lane " << l;
    }
  }
}

TEST(Simd16, ExpNonpositiveIsWithinItsStatedError) {
  // 2.5e-7 relative (simd16.h), 0 below -87, NaN for NaN.
  std::vector<float> xs;
  for (int i = 0; i <= 450000; ++i) xs.push_back(-90.0f * float(i) / 450000.0f);
  xs.push_back(-0.0f), xs.push_back(-87.0f), xs.push_back(std::nextafter(-87.0f, 0.0f)), xs.push_back(-1e-30f);
  xs.push_back(-kInf), xs.push_back(kNaN), xs.push_back(-FLT_MAX);
  while (xs.size() % kLanes) xs.push_back(-1.0f);
  for (size_t i = 0; i < xs.size(); i += kLanes) {
    const Floats r = out(exp_nonpositive(load(&xs[i])));
    for (int l = 0; l < kLanes; ++l) {
      const float x = xs[i + l];
      if (std::isnan(x)) {
        ASSERT_TRUE(std::isnan(r.v[l]));
      } else if (x < -87.0f) {
        ASSERT_TRUE(same(r.v[l], 0.0f)) << "exp(" << x << ")";
      } else {
        const double want = std::exp(double(x));
        ASSERT_LE(std::fabs(double(r.v[l]) - want), 2.5e-7 * want) << "exp(" << x << ")";
      }
    }
  }
}

// Pages around a buffer that fault when touched: a lane that should not read or write
// memory and does, crashes the test.
struct GuardedFloats {
  size_t page = size_t(sysconf(_SC_PAGESIZE));
  char* base = nullptr;
  float* data = nullptr;  // `page` bytes, a guard page before and after
  GuardedFloats() {
    base = static_cast<char*>(mmap(nullptr, 3 * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
    if (base == MAP_FAILED) throw std::runtime_error("mmap failed");
    mprotect(base, page, PROT_NONE), mprotect(base + 2 * page, page, PROT_NONE);
    data = reinterpret_cast<float*>(base + page);
  }
  ~GuardedFloats() { munmap(base, 3 * page); }
  int64_t size() const { return int64_t(page / sizeof(float)); }
};

TEST(Simd16, MaskedLoadsStoresAndGathersTouchOnlyTheirLanes) {
  GuardedFloats g;
  const int64_t n = g.size();
  for (int64_t i = 0; i < n; ++i) g.data[i] = float(i) * 0.25f - 3.0f;
  const std::vector<Mask> ms = masks(8);
  for (Mask m : ms) {
    // 16 lanes at offset o of the buffer: lanes before its start (o < 0) or after its end
    // are outside the mask, so only mapped memory may be read.
    for (int64_t o : {int64_t(-15), int64_t(-8), int64_t(-1), int64_t(0), int64_t(3), n - 16, n - 9, n - 1}) {
      Mask inside = 0;
      for (int l = 0; l < kLanes; ++l) inside |= Mask(o + l >= 0 && o + l < n) << l;
      const Mask mm = m & (inside | ~kAll);  // bits above lane 15 stay: they must be ignored
      const Floats r = out(load(g.data + o, mm, -7.5f));
      for (int l = 0; l < kLanes; ++l)
        ASSERT_TRUE(same(r.v[l], (mm >> l & 1) ? g.data[o + l] : -7.5f)) << "load mask " << mm << " lane " << l;
      if (o >= 0 && o + kLanes <= n) {
        const Floats full = out(load(g.data + o));
        for (int l = 0; l < kLanes; ++l) ASSERT_TRUE(same(full.v[l], g.data[o + l]));
      }
      // A masked store writes its lanes and leaves the others as they were.
      std::vector<float> before(g.data, g.data + n);
      float vals[kLanes];
      for (int l = 0; l < kLanes; ++l) vals[l] = 1000.0f + float(l);
      store(g.data + o, load(vals), mm);
      for (int64_t i = 0; i < n; ++i) {
        const int64_t l = i - o;
        const bool written = l >= 0 && l < kLanes && (mm >> l & 1);
        ASSERT_TRUE(same(g.data[i], written ? vals[l] : before[size_t(i)])) << "store mask " << mm << " at " << i;
      }
      std::copy(before.begin(), before.end(), g.data);
    }
    // A gather reads base[idx] for its lanes; the others hold indices far outside the
    // buffer (the guard pages, or INT_MIN / INT_MAX) and read `fill`.
    alignas(64) float idx_bits[kLanes];
    int32_t idx[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      idx[l] = (m >> l & 1) ? int32_t((l * 97 + int64_t(m)) % n)
                            : std::vector<int32_t>{-1, int32_t(n), INT32_MIN, INT32_MAX, -100, int32_t(n) + 5}[l % 6];
      idx_bits[l] = std::bit_cast<float>(idx[l]);
    }
    VI vi;
    const VF f = load(idx_bits);
    std::memcpy(&vi, &f, sizeof vi);
    const Floats r = out(gather(g.data, vi, m, kNaN));
    for (int l = 0; l < kLanes; ++l)
      ASSERT_TRUE(same(r.v[l], (m >> l & 1) ? g.data[idx[l]] : kNaN)) << "gather mask " << m << " lane " << l;
  }
}

}  // namespace
