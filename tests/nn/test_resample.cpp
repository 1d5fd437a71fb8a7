#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "nn/functional/resample.h"
#include "nn/resample.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

namespace {
// PyTorch's general bilinear rule (align_corners=False) written directly, as the
// reference for the specialised x2 kernel.
double upsample_reference(const TensorD& x, int64_t p, int64_t oy, int64_t ox) {
  const int64_t H = x.size(2), W = x.size(3);
  auto coord = [](int64_t o, int64_t n, int64_t& i0, int64_t& i1, double& l) {
    double s = std::max((o + 0.5) / 2.0 - 0.5, 0.0);
    i0 = int64_t(s);
    i1 = std::min(i0 + 1, n - 1);
    l = s - double(i0);
  };
  int64_t y0, y1, x0, x1;
  double ly, lx;
  coord(oy, H, y0, y1, ly);
  coord(ox, W, x0, x1, lx);
  const double* d = x.data() + p * H * W;
  return (1 - ly) * ((1 - lx) * d[y0 * W + x0] + lx * d[y0 * W + x1]) +
         ly * ((1 - lx) * d[y1 * W + x0] + lx * d[y1 * W + x1]);
}
}  // namespace

TEST(Upsample, MatchesPyTorchHandCase) {
  Var<double> x(Tensor<double>::from({1, 1, 2, 2}, {1, 2, 3, 4}));
  auto y = upsample_bilinear2x(x);
  // torch.nn.Upsample(scale_factor=2, mode='bilinear', align_corners=False)
  std::vector<double> want = {1.0, 1.25, 1.75, 2.0, 1.5, 1.75, 2.25, 2.5, 2.5, 2.75, 3.25, 3.5, 3.0, 3.25, 3.75, 4.0};
  ASSERT_EQ(y.shape(), Shape({1, 1, 4, 4}));
  for (int i = 0; i < 16; ++i) EXPECT_DOUBLE_EQ(y.value()[i], want[size_t(i)]) << i;
}

TEST(Upsample, MatchesReferenceOnOddSizes) {
  Rng rng(71);
  for (Shape s : {Shape{2, 3, 3, 5}, Shape{1, 1, 1, 1}, Shape{1, 2, 1, 4}}) {
    TensorD x = random_tensor(s, rng);
    auto y = upsample_bilinear2x(VarD(x));
    const int64_t Ho = 2 * s[2], Wo = 2 * s[3];
    for (int64_t p = 0; p < s[0] * s[1]; ++p)
      for (int64_t oy = 0; oy < Ho; ++oy)
        for (int64_t ox = 0; ox < Wo; ++ox)
          EXPECT_NEAR(y.value()[(p * Ho + oy) * Wo + ox], upsample_reference(x, p, oy, ox), 1e-14);
  }
}

TEST(Upsample, GradCheck) {
  Rng rng(72);
  std::vector<VarD> in = {VarD(random_tensor({2, 3, 3, 5}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return upsample_bilinear2x(v[0]); }, in);
  std::vector<VarD> tiny = {VarD(random_tensor({1, 2, 1, 2}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return upsample_bilinear2x(v[0]); }, tiny);
}

TEST(AvgPool, ForwardHandComputedAndOddFloor) {
  Var<float> x(Tensor<float>::from({1, 1, 2, 4}, {1, 2, 3, 4, 5, 6, 7, 8}));
  auto y = avg_pool2x2(x);
  ASSERT_EQ(y.shape(), Shape({1, 1, 1, 2}));
  EXPECT_FLOAT_EQ(y.value()[0], 3.5f);
  EXPECT_FLOAT_EQ(y.value()[1], 5.5f);
  Var<float> odd(Tensor<float>::zeros({1, 2, 5, 3}));
  EXPECT_EQ(avg_pool2x2(odd).shape(), Shape({1, 2, 2, 1}));
  EXPECT_THROW(avg_pool2x2(Var<float>(Tensor<float>::zeros({4, 4}))), std::invalid_argument);
}

TEST(AvgPool, GradCheck) {
  Rng rng(73);
  std::vector<VarD> in = {VarD(random_tensor({2, 3, 4, 6}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return avg_pool2x2(v[0]); }, in);
  std::vector<VarD> odd = {VarD(random_tensor({1, 2, 5, 7}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return avg_pool2x2(v[0]); }, odd);
}

TEST(Resample, ModulesRoundTripShapes) {
  AvgPool2x2<float> pool;
  UpsampleBilinear2x<float> up;
  Var<float> x(Tensor<float>::ones({1, 2, 6, 8}));
  auto y = up.forward(pool.forward(x));
  EXPECT_EQ(y.shape(), x.shape());
  for (float v : y.value()) EXPECT_FLOAT_EQ(v, 1.0f);  // constants survive both
}
