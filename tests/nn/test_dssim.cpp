#include <gtest/gtest.h>

#include <cmath>

#include "nn/losses/dssim.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

namespace {
TensorD uniform_tensor(const Shape& s, Rng& rng) {
  TensorD t(s);
  for (auto& v : t) v = rng.uniform();
  return t;
}
// SSIM straight from the definition: a 2-d 11x11 Gaussian window at every valid
// position, as the reference for the separable kernel.
double ssim_reference(const TensorD& a, const TensorD& b) {
  const int64_t H = a.shape()[-2], W = a.shape()[-1], P = a.numel() / (H * W);
  double g[11], gs = 0;
  for (int k = 0; k < 11; ++k) gs += g[k] = std::exp(-(k - 5) * (k - 5) / (2 * 1.5 * 1.5));
  const double C1 = 1e-4, C2 = 9e-4;
  double total = 0;
  int64_t count = 0;
  for (int64_t p = 0; p < P; ++p)
    for (int64_t i = 0; i + 11 <= H; ++i)
      for (int64_t j = 0; j + 11 <= W; ++j) {
        double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
        for (int u = 0; u < 11; ++u)
          for (int v = 0; v < 11; ++v) {
            const double w = g[u] * g[v] / (gs * gs);
            const double x = a[(p * H + i + u) * W + j + v], y = b[(p * H + i + u) * W + j + v];
            mx += w * x;
            my += w * y;
            xx += w * x * x;
            yy += w * y * y;
            xy += w * x * y;
          }
        const double sxx = xx - mx * mx, syy = yy - my * my, sxy = xy - mx * my;
        total += (2 * mx * my + C1) * (2 * sxy + C2) / ((mx * mx + my * my + C1) * (sxx + syy + C2));
        ++count;
      }
  return total / double(count);
}
}  // namespace

TEST(SSIM, IdenticalIsOneAndConstantsHandComputed) {
  Rng rng(91);
  TensorD a = uniform_tensor({1, 3, 16, 12}, rng);
  EXPECT_NEAR(ssim(a, a), 1.0, 1e-12);
  // Constant images a, b: variances vanish, SSIM = (2ab + C1) / (a^2 + b^2 + C1).
  TensorD x = TensorD::full({1, 1, 11, 11}, 0.2), y = TensorD::full({1, 1, 11, 11}, 0.6);
  EXPECT_NEAR(ssim(x, y), (2 * 0.2 * 0.6 + 1e-4) / (0.04 + 0.36 + 1e-4), 1e-12);
}

TEST(SSIM, MatchesDirectDefinition) {
  Rng rng(92);
  TensorD a = uniform_tensor({2, 2, 14, 17}, rng), b = a.clone();
  for (auto& v : b) v = std::min(1.0, std::max(0.0, v + 0.2 * rng.normal()));
  EXPECT_NEAR(ssim(a, b), ssim_reference(a, b), 1e-12);
  Var<double> loss = dssim_loss(VarD(a), VarD(b));
  EXPECT_EQ(loss.shape(), Shape{});
  EXPECT_NEAR(loss.value()[0], (1 - ssim_reference(a, b)) / 2, 1e-12);
}

TEST(SSIM, GradCheck) {
  Rng rng(93);
  std::vector<VarD> in = {VarD(uniform_tensor({2, 2, 12, 13}, rng), true),
                          VarD(uniform_tensor({2, 2, 12, 13}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return dssim_loss(v[0], v[1]); }, in);
}

TEST(SSIM, RejectsSmallImages) {
  Var<float> a(Tensor<float>::zeros({1, 1, 8, 8}));
  EXPECT_THROW(dssim_loss(a, a), std::invalid_argument);
}
