#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "core/kernels/conv2d_reference.h"
#include "core/kernels/conv_transpose2d.h"
#include "nn/conv_transpose2d.h"
#include "nn/functional/conv2d.h"
#include "nn/functional/conv_transpose2d.h"
#include "tests/support/gradcheck.h"
#include "core/kernels/gemm_precision.h"
#include "tests/support/kernel_pair_check.h"

using namespace nns;
using namespace nns::testing;

namespace {

// In PyTorch's names: input (N, C_in, H, W), weight (C_in, C_out/groups, kh, kw).
struct Case {
  int64_t N, C_in, H, W, C_out, kh, kw;
  ConvTranspose2dParams p;
};

// Odd shapes: non-square, batch > 1, stride 2, padding, output_padding 1, dilation 2,
// groups 2, 1x1 kernels.
const Case kCases[] = {
    {2, 3, 4, 5, 2, 4, 4, ConvTranspose2dParams::square(2, 1)},     // the U-Net's up step
    {1, 4, 3, 4, 6, 3, 3, ConvTranspose2dParams::square(2, 1, 1)},  // output_padding 1
    {2, 4, 5, 3, 2, 3, 2, {2, 1, 1, 0, 1, 0, 1, 2, 2}},  // stride (2,1), pad (1,0), op (1,0), dil (1,2), groups 2
    {1, 2, 4, 4, 3, 3, 3, ConvTranspose2dParams::square(1, 1, 1, 2)},     // op 1 >= stride, < dilation 2
    {3, 5, 3, 2, 4, 1, 1, {}},                                            // 1x1: a plain GEMM
    {2, 4, 3, 3, 2, 1, 1, ConvTranspose2dParams::square(2, 0, 1, 1, 2)},  // 1x1 stride 2, groups 2
    {4, 16, 32, 32, 8, 4, 4, ConvTranspose2dParams::square(2, 1)},        // blocks split over threads
    {1, 4, 3, 512, 64, 3, 3, ConvTranspose2dParams::square(1, 1)},        // one-row blocks that overlap
};

ConvGeometry geometry_of(const Case& c) {
  return conv_transpose2d_geometry(c.N, c.C_in, c.H, c.W, c.C_out, c.kh, c.kw, c.p.stride_h, c.p.stride_w, c.p.pad_h,
                                   c.p.pad_w, c.p.out_pad_h, c.p.out_pad_w, c.p.dil_h, c.p.dil_w, c.p.groups);
}

}  // namespace

TEST(ConvTranspose2d, OutputShapeFollowsPyTorchFormula) {
  Rng rng(1);
  for (const Case& c : kCases) {
    Var<float> x(randn_float({c.N, c.C_in, c.H, c.W}, rng));
    Var<float> w(randn_float({c.C_in, c.C_out / c.p.groups, c.kh, c.kw}, rng));
    Var<float> y = conv_transpose2d(x, w, Var<float>(), c.p);
    auto out = [](int64_t in, int64_t k, int64_t s, int64_t p, int64_t op, int64_t d) {
      return (in - 1) * s - 2 * p + d * (k - 1) + op + 1;
    };
    EXPECT_EQ(y.shape(), (Shape{c.N, c.C_out, out(c.H, c.kh, c.p.stride_h, c.p.pad_h, c.p.out_pad_h, c.p.dil_h),
                                out(c.W, c.kw, c.p.stride_w, c.p.pad_w, c.p.out_pad_w, c.p.dil_w)}));
  }
  // pix2pix's up step doubles the size: 128 -> 64 channels, k4 s2 p1.
  Var<float> x(Tensor<float>::zeros({1, 2, 8, 6}));
  Var<float> w(Tensor<float>::zeros({2, 3, 4, 4}));
  EXPECT_EQ(conv_transpose2d(x, w, Var<float>(), ConvTranspose2dParams::square(2, 1)).shape(), (Shape{1, 3, 16, 12}));
}

TEST(ConvTranspose2d, ForwardHandComputed) {
  // k2 s2: every input pixel paints its own 2x2 copy of the kernel, scaled.
  Var<float> x(Tensor<float>::from({1, 1, 2, 2}, {1, 2, 3, 4}));
  Var<float> w(Tensor<float>::from({1, 1, 2, 2}, {1, 10, 100, 1000}));
  Var<float> b(Tensor<float>::from({1}, {0.5f}));
  Var<float> y = conv_transpose2d(x, w, b, ConvTranspose2dParams::square(2));
  ASSERT_EQ(y.shape(), (Shape{1, 1, 4, 4}));
  const float expect[16] = {1, 10, 2, 20, 100, 1000, 200, 2000, 3, 30, 4, 40, 300, 3000, 400, 4000};
  for (int i = 0; i < 16; ++i) EXPECT_FLOAT_EQ(y.value()[i], expect[i] + 0.5f) << "at " << i;

  // k3 s1 p1 on a single pixel: the kernel itself, cropped by the padding to 1x1.
  Var<float> one(Tensor<float>::from({1, 1, 1, 1}, {2}));
  Var<float> w3(Tensor<float>::from({1, 1, 3, 3}, {1, 2, 3, 4, 5, 6, 7, 8, 9}));
  Var<float> y3 = conv_transpose2d(one, w3, Var<float>(), ConvTranspose2dParams::square(1, 1));
  ASSERT_EQ(y3.shape(), (Shape{1, 1, 1, 1}));
  EXPECT_FLOAT_EQ(y3.value()[0], 10.0f);  // the centre tap
  // Same with output_padding 1 and stride 2: one extra row and column, reaching taps (2,2)...
  Var<float> y4 = conv_transpose2d(one, w3, Var<float>(), ConvTranspose2dParams::square(2, 1, 1));
  ASSERT_EQ(y4.shape(), (Shape{1, 1, 2, 2}));
  const float e4[4] = {10, 12, 16, 18};
  for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(y4.value()[i], e4[i]);
}

// The transposed convolution is the adjoint of the convolution with the same weight:
// <conv(x), y> == <x, conv_transpose(y)>.
TEST(ConvTranspose2d, IsTheAdjointOfConv2d) {
  Rng rng(4);
  for (const Case& c : kCases) {
    ConvGeometry g = geometry_of(c);
    Conv2dParams cp{c.p.stride_h, c.p.stride_w, c.p.pad_h, c.p.pad_w, c.p.dil_h, c.p.dil_w, c.p.groups};
    auto w = random_tensor({c.C_in, c.C_out / c.p.groups, c.kh, c.kw}, rng);
    auto y = random_tensor({c.N, c.C_in, c.H, c.W}, rng);   // transposed input
    auto x = random_tensor({c.N, c.C_out, g.H, g.W}, rng);  // transposed output
    VarD cx = conv2d(VarD(x), VarD(w), VarD(), cp);
    VarD ty = conv_transpose2d(VarD(y), VarD(w), VarD(), c.p);
    // conv2d may produce one extra row/column that the transposed op does not reach.
    ASSERT_GE(cx.size(2), c.H);
    ASSERT_GE(cx.size(3), c.W);
    double lhs = 0, rhs = 0;
    for (int64_t n = 0; n < c.N; ++n)
      for (int64_t ch = 0; ch < c.C_in; ++ch)
        for (int64_t i = 0; i < c.H; ++i)
          for (int64_t j = 0; j < c.W; ++j)
            lhs += cx.value()[((n * c.C_in + ch) * cx.size(2) + i) * cx.size(3) + j] *
                   y[((n * c.C_in + ch) * c.H + i) * c.W + j];
    for (int64_t i = 0; i < x.numel(); ++i) rhs += x[i] * ty.value()[i];
    EXPECT_NEAR(lhs, rhs, 1e-9 * (1 + std::abs(lhs)));
  }
}

// Buffers for one case of kCases (g.H, g.W are the output size); the fast pair on them.
LayerBuffers random_buffers(const Case& c, const ConvGeometry& g, Rng& rng) {
  return random_layer_buffers({c.N, c.C_in, c.H, c.W}, {c.C_in, c.C_out / c.p.groups, c.kh, c.kw}, {c.C_out},
                              {c.N, c.C_out, g.H, g.W}, rng);
}

std::array<Tensor<float>, 4> run_fast(const LayerBuffers& in, const ConvGeometry& g) {
  return forward_backward(
      in, [&](auto... a) { conv_transpose2d_forward(a..., g); },
      [&](auto... a) { conv_transpose2d_backward(a..., g); });
}

TEST(ConvTranspose2d, FastKernelsMatchReference) {
  Rng rng(2);
  for (const Case& c : kCases) {
    ConvGeometry g = geometry_of(c);
    LayerBuffers in = random_buffers(c, g, rng);
    expect_close(run_fast(in, g), forward_backward<double>(
                                      in, [&](auto... a) { conv_transpose2d_forward_reference(a..., g); },
                                      [&](auto... a) { conv_transpose2d_backward_reference(a..., g); }));
  }
}

namespace {
void expect_all_cases_same_bits_on_1_and_2_threads() {
  // All cases with one thread, then all with two: the pool is resized only twice.
  expect_same_bits_on_1_and_2_threads(3, [](Rng& rng) {
    std::vector<std::array<Tensor<float>, 4>> out;
    for (const Case& c : kCases) {
      ConvGeometry g = geometry_of(c);
      out.push_back(run_fast(random_buffers(c, g, rng), g));
    }
    return out;
  });
}
}  // namespace

TEST(ConvTranspose2d, OneAndTwoThreadsAgreeBitwise) { expect_all_cases_same_bits_on_1_and_2_threads(); }

TEST(ConvTranspose2d, GradCheck) {
  for (size_t i = 0; i + 2 < std::size(kCases); ++i) {  // the last two cases are only large
    const Case& c = kCases[i];
    SCOPED_TRACE("case " + std::to_string(i));
    Rng rng(10 + i);
    std::vector<VarD> in = {VarD(random_tensor({c.N, c.C_in, c.H, c.W}, rng), true),
                            VarD(random_tensor({c.C_in, c.C_out / c.p.groups, c.kh, c.kw}, rng), true),
                            VarD(random_tensor({c.C_out}, rng), true)};
    const ConvTranspose2dParams p = c.p;
    gradcheck([p](std::vector<VarD>& v) { return conv_transpose2d(v[0], v[1], v[2], p); }, in);
  }
}

TEST(ConvTranspose2d, ModuleParametersAndInit) {
  Rng rng(5);
  ConvTranspose2d<float> up(rng, 6, 4, 4, 2, 1, /*output_padding=*/0, /*bias=*/true,
                            /*dilation=*/1, /*groups=*/2);
  auto named = up.named_parameters();
  ASSERT_EQ(named.size(), 2u);
  EXPECT_EQ(named[0].first, "weight");
  EXPECT_EQ(named[1].first, "bias");
  EXPECT_EQ(up.weight.shape(), (Shape{6, 2, 4, 4}));
  EXPECT_EQ(up.bias.shape(), (Shape{4}));
  // PyTorch's fan_in for a transposed conv is weight.size(1) * kh * kw = 2 * 16.
  const double bound = 1.0 / std::sqrt(32.0);
  double maxabs = 0;
  for (float v : up.weight.value()) maxabs = std::max(maxabs, std::abs(double(v)));
  EXPECT_LE(maxabs, bound);
  EXPECT_GT(maxabs, 0.8 * bound);
  Var<float> x(randn_float({2, 6, 5, 3}, rng));
  EXPECT_EQ(up.forward(x).shape(), (Shape{2, 4, 10, 6}));
  ConvTranspose2d<float> nobias(rng, 4, 4, 3, 1, 1, 0, /*bias=*/false);
  EXPECT_EQ(nobias.named_parameters().size(), 1u);
}

TEST(ConvTranspose2d, BadArgumentsAreNamed) {
  Rng rng(6);
  Var<float> x(randn_float({1, 3, 4, 4}, rng));
  Var<float> w(randn_float({2, 2, 3, 3}, rng));
  EXPECT_THROW(conv_transpose2d(x, w), std::invalid_argument);
  Var<float> w3(randn_float({3, 2, 3, 3}, rng));
  try {  // output_padding must be smaller than stride or dilation
    conv_transpose2d(x, w3, Var<float>(), ConvTranspose2dParams::square(1, 0, 1));
    FAIL() << "output_padding 1 with stride 1 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("output_padding"), std::string::npos);
  }
}

// Precision::bf16 through every path (im2col, implicit GEMM, packed weights, skinny and
// tiny products).
TEST(ConvTranspose2d, Bf16MatchesReferenceOnRoundedOperands) {
  const ScopedGemmPrecision bf16(Precision::bf16);
  Rng rng(2);
  for (const Case& c : kCases) {
    ConvGeometry g = geometry_of(c);
    LayerBuffers in = random_buffers(c, g, rng);
    expect_bf16_matches_reference(
        run_fast(in, g), in, [&](auto... a) { conv_transpose2d_forward_reference(a..., g); },
        [&](auto... a) { conv_transpose2d_backward_reference(a..., g); });
  }
}

TEST(ConvTranspose2d, Bf16OneAndTwoThreadsAgreeBitwise) {
  const ScopedGemmPrecision bf16(Precision::bf16);
  expect_all_cases_same_bits_on_1_and_2_threads();
}
