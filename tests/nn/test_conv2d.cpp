#include <gtest/gtest.h>

#include <cmath>

#include "core/kernels/conv2d.h"
#include "core/kernels/conv2d_reference.h"
#include "nn/conv2d.h"
#include "nn/functional/conv2d.h"
#include "tests/support/gradcheck.h"
#include "core/kernels/gemm_precision.h"
#include "tests/support/kernel_pair_check.h"

using namespace nns;
using namespace nns::testing;

namespace {

struct Case {
  int64_t N, C_in, H, W, C_out, kh, kw;
  Conv2dParams p;
};

// Odd shapes: non-square, batch > 1, stride 2, padding, dilation 2, groups 2, 1x1, one
// output channel (core/kernels/conv2d_direct.h instead of im2col + GEMM).
const Case kCases[] = {
    {2, 3, 7, 6, 4, 3, 3, Conv2dParams::square(1, 1)},
    {1, 4, 9, 8, 6, 4, 4, Conv2dParams::square(2, 1)},
    {2, 4, 8, 11, 6, 3, 2, {2, 1, 1, 0, 1, 2, 2}},         // stride (2,1), pad (1,0), dil (1,2), groups 2
    {1, 2, 9, 9, 3, 3, 3, Conv2dParams::square(1, 2, 2)},  // dilation 2
    {3, 5, 4, 3, 2, 1, 1, {}},                             // 1x1: skips im2col
    {2, 4, 5, 6, 4, 1, 1, {2, 2, 0, 0, 1, 1, 2}},          // 1x1 with stride 2 and groups 2: im2col path
    {2, 3, 7, 6, 1, 4, 4, Conv2dParams::square(2, 1)},     // one output channel: direct path
    {2, 16, 64, 64, 8, 3, 3, Conv2dParams::square(1, 1)},  // several row blocks per image
    {1, 64, 3, 512, 4, 3, 3, Conv2dParams::square(1, 1)},  // one-row blocks that overlap
    // Implicit GEMM (stride_w 1, K > 32): micro-panels that straddle output rows (W_out 37),
    // a 4x4 kernel, and stride_h 2 with dilation 2 and unequal padding.
    {1, 8, 13, 37, 20, 3, 3, Conv2dParams::square(1, 1)},
    {2, 8, 10, 35, 24, 4, 4, Conv2dParams::square(1, 1)},
    {1, 6, 11, 40, 16, 3, 3, {2, 1, 2, 1, 2, 2, 1}},
    // Strided rows (im2col; implicit measured no faster there): k4 s2 p1 with W_out 35, and
    // stride_w 3 with dilation 2.
    {1, 5, 6, 70, 18, 4, 4, Conv2dParams::square(2, 1)},
    {1, 4, 7, 50, 9, 3, 3, {1, 3, 1, 2, 1, 2, 1}},
};
// The cases from here on are too large for the double-precision gradient check.
constexpr size_t kFirstLargeCase = 7;

ConvGeometry geometry_of(const Case& c) {
  return conv2d_geometry(c.N, c.C_in, c.H, c.W, c.C_out, c.kh, c.kw, c.p.stride_h, c.p.stride_w, c.p.pad_h, c.p.pad_w,
                         c.p.dil_h, c.p.dil_w, c.p.groups);
}

}  // namespace

TEST(Conv2d, OutputShapeFollowsPyTorchFormula) {
  Rng rng(1);
  for (const Case& c : kCases) {
    Var<float> x(randn_float({c.N, c.C_in, c.H, c.W}, rng));
    Var<float> w(randn_float({c.C_out, c.C_in / c.p.groups, c.kh, c.kw}, rng));
    Var<float> y = conv2d(x, w, Var<float>(), c.p);
    auto out = [](int64_t in, int64_t k, int64_t s, int64_t p, int64_t d) {
      return int64_t(std::floor(double(in + 2 * p - d * (k - 1) - 1) / s)) + 1;
    };
    EXPECT_EQ(y.shape(), (Shape{c.N, c.C_out, out(c.H, c.kh, c.p.stride_h, c.p.pad_h, c.p.dil_h),
                                out(c.W, c.kw, c.p.stride_w, c.p.pad_w, c.p.dil_w)}));
  }
}

TEST(Conv2d, ForwardHandComputed) {
  // x = 1..9 in a 3x3 grid, 2x2 kernel [[1,0],[0,-1]] (x[i][j] - x[i+1][j+1] = -4), bias 0.5,
  // padding 1: corners see a single tap.
  Var<float> x(Tensor<float>::from({1, 1, 3, 3}, {1, 2, 3, 4, 5, 6, 7, 8, 9}));
  Var<float> w(Tensor<float>::from({1, 1, 2, 2}, {1, 0, 0, -1}));
  Var<float> b(Tensor<float>::from({1}, {0.5f}));
  Var<float> y = conv2d(x, w, b, Conv2dParams::square(1, 1));
  ASSERT_EQ(y.shape(), (Shape{1, 1, 4, 4}));
  const float expect[16] = {-0.5f, -1.5f, -2.5f, 0.5f, -3.5f, -3.5f, -3.5f, 3.5f,
                            -6.5f, -3.5f, -3.5f, 6.5f, 0.5f,  7.5f,  8.5f,  9.5f};
  for (int i = 0; i < 16; ++i) EXPECT_FLOAT_EQ(y.value()[i], expect[i]) << "at " << i;

  // Stride 2 with groups 2: each output channel sees only its own input channel.
  Var<float> x2(Tensor<float>::from({1, 2, 2, 2}, {1, 2, 3, 4, 10, 20, 30, 40}));
  Var<float> w2(Tensor<float>::from({2, 1, 1, 1}, {2, -1}));
  Var<float> y2 = conv2d(x2, w2, Var<float>(), Conv2dParams::square(2, 0, 1, 2));
  ASSERT_EQ(y2.shape(), (Shape{1, 2, 1, 1}));
  EXPECT_FLOAT_EQ(y2.value()[0], 2.0f);
  EXPECT_FLOAT_EQ(y2.value()[1], -10.0f);
}

// Buffers for one case of kCases; the fast pair or the reference pair on them.
LayerBuffers random_buffers(const ConvGeometry& g, Rng& rng) {
  return random_layer_buffers({g.N, g.C_in, g.H, g.W}, {g.C_out, g.cin_g(), g.kh, g.kw}, {g.C_out},
                              {g.N, g.C_out, g.H_out, g.W_out}, rng);
}

std::array<Tensor<float>, 4> run_fast(const LayerBuffers& in, const ConvGeometry& g) {
  return forward_backward(
      in, [&](auto... a) { conv2d_forward(a..., g); }, [&](auto... a) { conv2d_backward(a..., g); });
}

TEST(Conv2d, FastKernelsMatchReference) {
  Rng rng(2);
  for (const Case& c : kCases) {
    ConvGeometry g = geometry_of(c);
    LayerBuffers in = random_buffers(g, rng);
    expect_close(run_fast(in, g), forward_backward<double>(
                                      in, [&](auto... a) { conv2d_forward_reference(a..., g); },
                                      [&](auto... a) { conv2d_backward_reference(a..., g); }));
  }
}

namespace {
void expect_all_cases_same_bits_on_1_and_2_threads() {
  // All cases with one thread, then all with two: the pool is resized only twice.
  expect_same_bits_on_1_and_2_threads(3, [](Rng& rng) {
    std::vector<std::array<Tensor<float>, 4>> out;
    for (const Case& c : kCases) {
      ConvGeometry g = geometry_of(c);
      out.push_back(run_fast(random_buffers(g, rng), g));
    }
    return out;
  });
}
}  // namespace

TEST(Conv2d, OneAndTwoThreadsAgreeBitwise) { expect_all_cases_same_bits_on_1_and_2_threads(); }

TEST(Conv2d, GradCheck) {
  for (size_t i = 0; i < kFirstLargeCase; ++i) {
    const Case& c = kCases[i];
    SCOPED_TRACE("case " + std::to_string(i));
    Rng rng(10 + i);
    std::vector<VarD> in = {VarD(random_tensor({c.N, c.C_in, c.H, c.W}, rng), true),
                            VarD(random_tensor({c.C_out, c.C_in / c.p.groups, c.kh, c.kw}, rng), true),
                            VarD(random_tensor({c.C_out}, rng), true)};
    const Conv2dParams p = c.p;
    gradcheck([p](std::vector<VarD>& v) { return conv2d(v[0], v[1], v[2], p); }, in);
  }
}

TEST(Conv2d, GradCheckWithoutBias) {
  Rng rng(20);
  std::vector<VarD> in = {VarD(random_tensor({2, 2, 5, 4}, rng), true), VarD(random_tensor({3, 2, 2, 3}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return conv2d(v[0], v[1], VarD(), Conv2dParams::square(2, 1)); }, in);
}

TEST(Conv2d, ModuleParametersAndInit) {
  Rng rng(5);
  Conv2d<float> conv(rng, 6, 8, 3, 2, 1, /*bias=*/true, /*dilation=*/1, /*groups=*/2);
  auto named = conv.named_parameters();
  ASSERT_EQ(named.size(), 2u);
  EXPECT_EQ(named[0].first, "weight");
  EXPECT_EQ(named[1].first, "bias");
  EXPECT_EQ(conv.weight.shape(), (Shape{8, 3, 3, 3}));
  EXPECT_EQ(conv.bias.shape(), (Shape{8}));
  // kaiming_uniform(a=sqrt(5)): U(-1/sqrt(fan_in), 1/sqrt(fan_in)), fan_in = 3*3*3.
  const double bound = 1.0 / std::sqrt(27.0);
  double maxabs = 0;
  for (float v : conv.weight.value()) maxabs = std::max(maxabs, std::abs(double(v)));
  EXPECT_LE(maxabs, bound);
  EXPECT_GT(maxabs, 0.8 * bound);  // 216 draws: the largest is close to the bound
  Var<float> x(randn_float({1, 6, 7, 5}, rng));
  EXPECT_EQ(conv.forward(x).shape(), (Shape{1, 8, 4, 3}));

  Conv2d<float> nobias(rng, 4, 4, 1, 1, 0, /*bias=*/false);
  EXPECT_EQ(nobias.named_parameters().size(), 1u);
  EXPECT_FALSE(nobias.bias.defined());

  // The same seed gives the same weights.
  Rng a(9), b(9);
  Conv2d<float> c1(a, 3, 4, 3), c2(b, 3, 4, 3);
  EXPECT_TRUE(bitwise_equal(c1.weight.value(), c2.weight.value()));
}

TEST(Conv2d, BadArgumentsAreNamed) {
  Rng rng(6);
  Var<float> x(randn_float({1, 3, 4, 4}, rng));
  Var<float> w(randn_float({2, 2, 3, 3}, rng));
  try {
    conv2d(x, w);
    FAIL() << "channel mismatch accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("conv2d"), std::string::npos);
  }
  Var<float> w5(randn_float({2, 3, 5, 5}, rng));
  EXPECT_THROW(conv2d(x, w5), std::invalid_argument);  // kernel larger than the input
  EXPECT_THROW(Conv2d<float>(rng, 3, 4, 3, 1, 0, true, 1, 2), std::invalid_argument);
}

// Precision::bf16 through every path (im2col, implicit GEMM, packed weights, skinny and
// tiny products).
TEST(Conv2d, Bf16MatchesReferenceOnRoundedOperands) {
  const ScopedGemmPrecision bf16(Precision::bf16);
  Rng rng(2);
  for (const Case& c : kCases) {
    ConvGeometry g = geometry_of(c);
    LayerBuffers in = random_buffers(g, rng);
    if (g.cout_g() == 1) continue;  // conv2d_direct.h: no GEMM, stays fp32
    expect_bf16_matches_reference(
        run_fast(in, g), in, [&](auto... a) { conv2d_forward_reference(a..., g); },
        [&](auto... a) { conv2d_backward_reference(a..., g); });
  }
}

TEST(Conv2d, Bf16OneAndTwoThreadsAgreeBitwise) {
  const ScopedGemmPrecision bf16(Precision::bf16);
  expect_all_cases_same_bits_on_1_and_2_threads();
}
