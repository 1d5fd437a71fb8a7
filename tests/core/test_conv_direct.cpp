// The direct convolution loops (core/kernels/conv2d_direct.h) against the naive
// reference, in both of their modes (assign / accumulate), with 1 and 2 threads. The
// layer tests in tests/nn reach them only through single-output-channel layers.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "core/kernels/conv2d.h"
#include "core/kernels/conv2d_direct.h"
#include "core/kernels/conv2d_reference.h"
#include "core/thread_pool.h"
#include "tests/support/kernel_pair_check.h"

using namespace nns;
using namespace nns::testing;

namespace {

// N, C_in, H, W, C_out, kh, kw, stride (h, w), pad (h, w), dil (h, w), groups
struct Case {
  int64_t N, C_in, H, W, C_out, kh, kw, sh, sw, ph, pw, dh, dw, groups;
};
const Case kCases[] = {
    {1, 64, 11, 11, 1, 4, 4, 1, 1, 1, 1, 1, 1, 1},  // PatchGAN's score layer, scaled down
    {2, 3, 7, 6, 2, 3, 3, 1, 1, 1, 1, 1, 1, 1},     // batch 2, two outputs
    {1, 4, 9, 8, 3, 4, 4, 2, 2, 1, 1, 1, 1, 1},     // stride 2
    {2, 4, 8, 11, 2, 3, 2, 2, 1, 1, 0, 1, 2, 2},    // stride (2,1), pad (1,0), dil (1,2), groups 2
    {1, 2, 9, 9, 1, 3, 3, 1, 1, 2, 2, 2, 2, 1},     // dilation 2
    {3, 5, 4, 3, 1, 1, 1, 1, 1, 0, 0, 1, 1, 1},     // 1x1
    {1, 3, 5, 5, 1, 5, 5, 3, 3, 0, 0, 1, 1, 1},     // stride 3, taps off the right edge
};

ConvGeometry geometry_of(const Case& c) {
  return conv2d_geometry(c.N, c.C_in, c.H, c.W, c.C_out, c.kh, c.kw, c.sh, c.sw, c.ph, c.pw, c.dh, c.dw, c.groups);
}

LayerBuffers random_buffers(const ConvGeometry& g, Rng& rng) {
  return random_layer_buffers({g.N, g.C_in, g.H, g.W}, {g.C_out, g.cin_g(), g.kh, g.kw}, {g.C_out},
                              {g.N, g.C_out, g.H_out, g.W_out}, rng);
}

std::array<Tensor<float>, 4> run_direct(const LayerBuffers& in, const ConvGeometry& g) {
  return forward_backward(
      in,
      [&](float* y, const float* x, const float* w, const float* b) {
        conv2d_direct_forward(y, x, w, b, g, /*accumulate=*/false);
      },
      [&](float* dx, float* dw, float* db, const float* dy, const float* x, const float* w) {
        channel_sum_add(db, dy, g.N, g.C_out, g.out_plane());
        conv2d_direct_backward_weight(dw, dy, x, g);
        conv2d_direct_backward_input(dx, dy, w, g, /*accumulate=*/true);
      });
}

std::array<Tensor<double>, 4> run_reference(const LayerBuffers& in, const ConvGeometry& g) {
  return forward_backward<double>(
      in, [&](auto... a) { conv2d_forward_reference(a..., g); },
      [&](auto... a) { conv2d_backward_reference(a..., g); });
}

TEST(ConvDirect, MatchesReference) {
  Rng rng(5);
  for (const Case& c : kCases) {
    SCOPED_TRACE("case C_in=" + std::to_string(c.C_in) + " C_out=" + std::to_string(c.C_out) +
                 " k=" + std::to_string(c.kh) + "x" + std::to_string(c.kw));
    ConvGeometry g = geometry_of(c);
    LayerBuffers in = random_buffers(g, rng);
    expect_close(run_direct(in, g), run_reference(in, g));
  }
}

TEST(ConvDirect, AccumulateAndAssignModes) {
  Rng rng(6);
  for (const Case& c : kCases) {
    ConvGeometry g = geometry_of(c);
    LayerBuffers in = random_buffers(g, rng);
    // Forward with accumulate adds onto what is there.
    Tensor<float> y0({g.N, g.C_out, g.H_out, g.W_out}), y1 = Tensor<float>::full(y0.shape(), 2.0f);
    conv2d_direct_forward(y0.data(), in.x.data(), in.w.data(), in.b.data(), g, false);
    conv2d_direct_forward(y1.data(), in.x.data(), in.w.data(), in.b.data(), g, true);
    for (int64_t i = 0; i < y0.numel(); ++i) EXPECT_NEAR(y1[i], y0[i] + 2.0f, 1e-4f) << i;
    // Input gradient without accumulate overwrites a NaN-filled buffer.
    Tensor<float> dx = Tensor<float>::full(in.x.shape(), NAN);
    Tensor<float> dx_ref = Tensor<float>::zeros(in.x.shape());
    conv2d_direct_backward_input(dx.data(), in.dy.data(), in.w.data(), g, false);
    conv2d_backward_reference<float>(dx_ref.data(), nullptr, nullptr, in.dy.data(), in.x.data(), in.w.data(), g);
    expect_close(dx, dx_ref, "dinp (assign)");
  }
}

TEST(ConvDirect, DispatchedForSingleOutputChannel) {
  // The layer entry points take the direct path for one output channel: same bits as
  // calling it directly.
  Rng rng(7);
  ConvGeometry g = geometry_of(kCases[0]);
  ASSERT_TRUE(conv_use_direct(g));
  LayerBuffers in = random_buffers(g, rng);
  auto via_layer = forward_backward(
      in, [&](auto... a) { conv2d_forward(a..., g); }, [&](auto... a) { conv2d_backward(a..., g); });
  auto direct = run_direct(in, g);
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(bitwise_equal(via_layer[k], direct[k])) << kLayerOutputNames[k];
}

TEST(ConvDirect, OneAndTwoThreadsAgreeBitwise) {
  // Big enough that every pass is split between the threads.
  const ConvGeometry g = conv2d_geometry(2, 96, 31, 31, 1, 4, 4, 1, 1, 1, 1, 1, 1, 1);
  std::array<Tensor<float>, 4> res[2];
  for (int t = 0; t < 2; ++t) {
    set_num_threads(t + 1);
    Rng rng(8);
    res[t] = run_direct(random_buffers(g, rng), g);
  }
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(bitwise_equal(res[0][k], res[1][k])) << kLayerOutputNames[k];
  Rng rng(8);
  expect_close(res[1], run_reference(random_buffers(g, rng), g));
}

}  // namespace
