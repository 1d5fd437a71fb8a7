#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tuple>
#include <vector>

#include "core/thread_pool.h"
#include "models/nnao/nnao_inference.h"
#include "models/nnao/nnao_inference_reference.h"
#include "fixtures/random_nnao_blob.h"
#include "fixtures/synthetic_gbuffer.h"

using namespace nns;

namespace {

// The network in double straight from the blob's raw tensors: standardise, 4 layers.
double reference_ao(const Blob& b, const std::vector<float>& f, int H, double base = 0) {
  const int64_t F = int64_t(f.size());
  auto t = [&](const std::string& n, Shape s) { return b.tensor<double>(n, s); };
  auto mean = t("feature_mean", {F}), sd = t("feature_std", {F}), ts = t("target_stats", {2});
  std::vector<double> x(static_cast<size_t>(F));
  for (int64_t k = 0; k < F; ++k) x[size_t(k)] = (f[size_t(k)] - mean[k]) / sd[k];
  const int64_t in[4] = {F, H, H, H}, out[4] = {H, H, H, 1};
  for (int l = 0; l < 4; ++l) {
    auto W = t("fc" + std::to_string(l) + ".weight", {out[l], in[l]});
    auto B = t("fc" + std::to_string(l) + ".bias", {out[l]});
    auto A = t("act" + std::to_string(l) + ".alpha", {out[l]});
    auto Bt = t("act" + std::to_string(l) + ".beta", {out[l]});
    std::vector<double> y(size_t(out[l]));
    for (int64_t o = 0; o < out[l]; ++o) {
      double s = B[o];
      for (int64_t i = 0; i < in[l]; ++i) s += W[o * in[l] + i] * x[size_t(i)];
      y[size_t(o)] = s > 0 ? Bt[o] * s : A[o] * s;
    }
    x = y;
  }
  return std::clamp(x[0] * ts[1] + ts[0] + base, 0.0, 1.0);
}

}  // namespace

TEST(NnaoInference, ExactMatchesDoubleReferenceWithUnfoldedStandardisation) {
  const int w = 7, H = 4;
  Blob blob = nns::fixtures::random_nnao_blob(w, H, 5);
  auto m = nnao::NnaoWeights::from_blob(blob);
  auto v = nns::fixtures::synthetic_view(40, 28, 2, 1);
  auto g = screen_space::gbuffer_from_view(v);
  std::vector<float> out(size_t(g.pixels()));
  nnao::infer_exact(m, g, out.data());
  std::vector<float> f(size_t(nnao::feature_count(w)));
  double worst = 0;
  for (int64_t i = 0; i < g.pixels(); ++i) {
    if (g.sky(i)) {
      EXPECT_EQ(out[size_t(i)], 1.0f);
      continue;
    }
    nnao::compute_features(g, int(i % g.width), int(i / g.width), w, f.data());
    worst = std::max(worst, std::abs(out[size_t(i)] - reference_ao(blob, f, H)));
  }
  EXPECT_LT(worst, 1e-4);
}

TEST(NnaoInference, ShaderStyleWithEveryFilterPixelIsExact) {
  // With at least w x w strata each cell holds one filter pixel: no approximation left.
  const int w = 7;
  auto m = nnao::NnaoWeights::from_blob(nns::fixtures::random_nnao_blob(w, 4, 6));
  auto v = nns::fixtures::synthetic_view(40, 28, 1, 1);
  auto g = screen_space::gbuffer_from_view(v);
  std::vector<float> exact(size_t(g.pixels())), shader(size_t(g.pixels()));
  nnao::infer_exact(m, g, exact.data());
  nnao::infer_shader_style(m, g, 64, shader.data(), /*blur=*/false);
  for (size_t i = 0; i < exact.size(); ++i) ASSERT_NEAR(shader[i], exact[i], 1e-4) << i;
}

TEST(NnaoInference, ShaderStyleIsUnbiasedOverJitter) {
  // With an identity head (alpha = beta = 1) AO is affine in the layer-0 sums, so the
  // average over jitter seeds must converge to the exact result.
  const int w = 15;
  auto m = nnao::NnaoWeights::from_blob(nns::fixtures::random_nnao_blob(w, 4, 7, /*linear_head=*/true));
  auto v = nns::fixtures::synthetic_view(48, 32, 4, 1);
  auto g = screen_space::gbuffer_from_view(v);
  const size_t n = size_t(g.pixels());
  std::vector<float> exact(n), one(n), acc(n, 0), tmp(n);
  nnao::infer_exact(m, g, exact.data());
  const int seeds = 64;
  for (int s = 0; s < seeds; ++s) {
    nnao::infer_shader_style(m, g, 16, tmp.data(), false, uint32_t(s));
    if (s == 0) one = tmp;
    for (size_t i = 0; i < n; ++i) acc[i] += tmp[i] / seeds;
  }
  double e1 = 0, ea = 0;
  for (size_t i = 0; i < n; ++i)
    if (!g.sky(int64_t(i))) e1 += std::pow(one[i] - exact[i], 2), ea += std::pow(acc[i] - exact[i], 2);
  EXPECT_GT(e1, 0);
  EXPECT_LT(ea, e1 / 16);  // variance falls as 1/seeds (64); a bias would not
}

TEST(NnaoInference, SameResultWithOneAndTwoThreads) {
  auto m = nnao::NnaoWeights::from_blob(nns::fixtures::random_nnao_blob(9, 4, 8));
  auto v = nns::fixtures::synthetic_view(40, 28, 0, 1);
  auto g = screen_space::gbuffer_from_view(v);
  std::vector<float> a(size_t(g.pixels())), b(a.size()), c(a.size()), d(a.size());
  set_num_threads(1);
  nnao::infer_exact(m, g, a.data());
  nnao::infer_shader_style(m, g, 32, c.data());
  set_num_threads(2);
  nnao::infer_exact(m, g, b.data());
  nnao::infer_shader_style(m, g, 32, d.data());
  EXPECT_EQ(a, b);
  EXPECT_EQ(c, d);
}

TEST(NnaoInference, BlobWithWrongKindOrShapeIsRejected) {
  Blob b = nns::fixtures::random_nnao_blob(5, 4, 9);
  b.set_kind("pix2pix");
  EXPECT_THROW(nnao::NnaoWeights::from_blob(b), std::runtime_error);
  Blob c = nns::fixtures::random_nnao_blob(5, 4, 9);
  c.set_config("window", 7);  // tensors are for w = 5
  EXPECT_THROW(nnao::NnaoWeights::from_blob(c), std::runtime_error);
}

TEST(NnaoInference, SampleGridLayouts) {
  int mx, my;
  nnao::sample_grid(64, 31, mx, my);
  EXPECT_EQ(mx * my, 64);
  nnao::sample_grid(128, 31, mx, my);
  EXPECT_EQ(mx * my, 128);
  nnao::sample_grid(256, 31, mx, my);
  EXPECT_EQ(mx * my, 256);
  nnao::sample_grid(16, 31, mx, my);
  EXPECT_EQ(mx, 4);
  EXPECT_EQ(my, 4);
}

namespace {

// Vectorised against scalar reference: the same expressions, so almost every pixel is
// equal to float precision; a sample on an exact half-pixel boundary may still round
// to the neighbouring pixel when the compiler fuses a multiply-add differently, and
// the blur's exp is a polynomial (relative error < 2e-7).
void expect_close_to_reference(const std::vector<float>& fast, const std::vector<float>& ref, const std::string& what) {
  size_t off = 0;
  double worst = 0, sum = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_FALSE(std::isnan(fast[i])) << what << " pixel " << i;
    const double d = std::abs(double(fast[i]) - ref[i]);
    off += d > 1e-5;
    worst = std::max(worst, d);
    sum += d;
  }
  std::printf("[vector vs scalar] %s: %zu of %zu pixels differ by > 1e-5, max %.3g\n", what.c_str(), off, ref.size(),
              worst);
  EXPECT_LE(double(off), 0.002 * double(ref.size())) << what;
  EXPECT_LT(sum / double(ref.size()), 1e-5) << what;
}

}  // namespace

TEST(NnaoInference, VectorisedPathsMatchScalarReferences) {
  // 50 wide: three full 16-pixel blocks and a 2-pixel tail; H = 4 (the compile-time
  // path) and H = 6 (the general one).
  for (int H : {4, 6}) {
    auto m = nnao::NnaoWeights::from_blob(nns::fixtures::random_nnao_blob(9, H, 11 + H));
    for (int variant : {0, 3}) {
      auto v = nns::fixtures::synthetic_view(50, 30, variant, 1);
      auto g = screen_space::gbuffer_from_view(v);
      const std::string tag = "H" + std::to_string(H) + " variant " + std::to_string(variant);
      std::vector<float> a(size_t(g.pixels())), b(a.size());
      nnao::infer_exact(m, g, a.data());
      nnao::infer_exact_reference(m, g, b.data());
      expect_close_to_reference(a, b, "exact " + tag);
      for (bool blur : {false, true})
        for (int n : {16, 64}) {
          nnao::infer_shader_style(m, g, n, a.data(), blur, 3);
          nnao::infer_shader_style_reference(m, g, n, b.data(), blur, 3);
          expect_close_to_reference(a, b, "shader " + std::to_string(n) + (blur ? " blurred " : " raw ") + tag);
        }
    }
  }
}

// A horizon-feature model (nnao_inputs.h): the vectorised march + fused layer 0 + blur
// (horizon_simd.h, infer_exact) against the per-pixel loop + scalar blur, that loop
// against the network in double from the raw tensors plus the visibility base, and
// both thread counts alike, on outputs spread over (0, 1) (the random weights alone
// clamp every pixel to 1). Layouts
// with an odd number of directions and 3 bands; hidden 4, 8 and 16 (the widths
// horizon_simd.h compiles in) and 6 (the runtime width); a 2-pixel tail block.
TEST(NnaoInference, HorizonModelMatchesPerPixelAndDoubleReferences) {
  const nns::fixtures::HorizonShape shapes[2] = {{8, 8, 4}, {5, 6, 3}};
  for (const auto& sh : shapes)
    for (int H : {4, 6, 8, 16}) {
      // Spread: the raw random weights clamp a horizon model's output to 1 on every
      // pixel, where a wrong march could not show.
      Blob blob = nns::fixtures::spread_nnao_outputs(nns::fixtures::random_nnao_blob(0, H, 21 + H, false, sh),
                                                     80.0f / float(H), -0.3f);
      auto m = nnao::NnaoWeights::from_blob(blob);
      ASSERT_TRUE(m.input.is_horizon());
      for (int variant : {0, 3}) {
        auto v = nns::fixtures::synthetic_view(50, 30, variant, 1);
        auto g = screen_space::gbuffer_from_view(v);
        const std::string tag = "horizon " + std::to_string(sh.directions) + "x" + std::to_string(sh.steps) + " H" +
                                std::to_string(H) + " variant " + std::to_string(variant);
        std::vector<float> a(size_t(g.pixels())), b(a.size()), c(a.size());
        set_num_threads(1);
        nnao::infer_exact(m, g, a.data());
        set_num_threads(2);
        nnao::infer_exact(m, g, c.data());
        EXPECT_EQ(a, c) << tag;
        int64_t inside = 0;
        for (float x : a) inside += x > 0 && x < 1;
        EXPECT_GT(inside, g.pixels() / 4) << tag;
        nnao::infer_exact_reference(m, g, b.data());
        expect_close_to_reference(a, b, "exact " + tag);
        // Before the blur: the per-pixel loop against the network in double.
        nnao::infer_exact_per_pixel(m, g, b.data());
        std::vector<float> f(size_t(m.features()));
        double worst = 0;
        for (int64_t i = 0; i < g.pixels(); ++i) {
          if (g.sky(i)) {
            EXPECT_EQ(a[size_t(i)], 1.0f);
            continue;
          }
          m.input.compute(g, int(i % g.width), int(i / g.width), f.data());
          worst = std::max(worst, std::abs(b[size_t(i)] - reference_ao(blob, f, H, m.input.base(f.data()))));
        }
        EXPECT_LT(worst, 1e-4) << tag;
      }
      EXPECT_THROW(nnao::check_sample_count(64, m.input), std::invalid_argument);
    }
}

// blur_passes N: the exact inference is the march, then the blur N times (vector and
// scalar alike); absent means 1; outside 1..16 the blob is refused.
TEST(NnaoInference, HorizonModelBlursBlurPassesTimes) {
  Blob blob =
      nns::fixtures::spread_nnao_outputs(nns::fixtures::random_nnao_blob(0, 8, 31, false, {8, 8, 4}), 10, -0.3f);
  ASSERT_EQ(nnao::NnaoWeights::from_blob(blob).blur_passes, 1);
  blob.set_config("blur_passes", 3);
  const auto m = nnao::NnaoWeights::from_blob(blob);
  ASSERT_EQ(m.blur_passes, 3);
  const auto view = nns::fixtures::synthetic_view(50, 30, 3, 1);  // g points into it
  auto g = screen_space::gbuffer_from_view(view);
  std::vector<float> raw(size_t(g.pixels())), once(raw.size()), expect(raw.size()), got(raw.size()), ref(raw.size());
  nnao::infer_horizon(m, g, raw.data());
  for (int p = 0; p < 3; ++p) {
    nnao::bilateral_blur(g, raw.data(), expect.data());
    if (p == 0) once = expect;
    raw = expect;
  }
  nnao::infer_exact(m, g, got.data());
  EXPECT_EQ(got, expect);
  EXPECT_NE(got, once);  // the passes change the image
  nnao::infer_exact_reference(m, g, ref.data());
  expect_close_to_reference(got, ref, "exact, 3 blur passes");
  for (int bad : {0, 17}) {
    blob.set_config("blur_passes", bad);
    EXPECT_THROW(nnao::NnaoWeights::from_blob(blob), std::runtime_error) << bad;
  }
}

// radius_term_max: absent or 0 mean no ceiling; present, the vector march and the
// per-pixel loop both hold the radius term at it; out of range the blob is refused.
TEST(NnaoInference, HorizonModelHoldsTheRadiusTermAtTheBlobsCeiling) {
  Blob blob =
      nns::fixtures::spread_nnao_outputs(nns::fixtures::random_nnao_blob(0, 8, 29, false, {8, 8, 4}), 10, -0.3f);
  ASSERT_FALSE(std::isfinite(nnao::NnaoWeights::from_blob(blob).input.horizon.radius_term_max));
  blob.set_config("radius_term_max", 0.0);
  ASSERT_FALSE(std::isfinite(nnao::NnaoWeights::from_blob(blob).input.horizon.radius_term_max));
  const auto plain = nnao::NnaoWeights::from_blob(blob);
  const auto view = nns::fixtures::synthetic_view(50, 30, 3, 1);  // g points into it
  auto g = screen_space::gbuffer_from_view(view);
  // A ceiling at the view's median radius term, so it holds half the pixels.
  std::vector<float> terms, f(size_t(plain.features()));
  for (int64_t i = 0; i < g.pixels(); ++i)
    if (!g.sky(i)) {
      plain.input.compute(g, int(i % g.width), int(i / g.width), f.data());
      terms.push_back(f[size_t(plain.features() - plain.input.horizon.bands - 1)]);
    }
  std::nth_element(terms.begin(), terms.begin() + terms.size() / 2, terms.end());
  const float ceiling = terms[terms.size() / 2];
  blob.set_config("radius_term_max", double(ceiling));
  const auto m = nnao::NnaoWeights::from_blob(blob);
  ASSERT_EQ(m.input.horizon.radius_term_max, ceiling);
  std::vector<float> vec(size_t(g.pixels())), loop(vec.size()), free(vec.size());
  nnao::infer_horizon(m, g, vec.data());
  nnao::infer_exact_per_pixel(m, g, loop.data());
  nnao::infer_horizon(plain, g, free.data());
  expect_close_to_reference(vec, loop, "radius term at most the median");
  int64_t changed = 0;
  for (size_t i = 0; i < vec.size(); ++i) changed += vec[i] != free[i];
  EXPECT_GT(changed, int64_t(terms.size() / 4)) << "the ceiling changed too few pixels to be in use";
  for (const char* bad : {"-0.5", "nan", "101", "x"}) {
    Blob b = blob;
    b.set_config("radius_term_max", bad);
    EXPECT_THROW(nnao::NnaoWeights::from_blob(b), std::runtime_error) << bad;
  }
  // Read from a file (a valid checksum, a bad value): the message names the file and the key.
  const std::string path = (std::filesystem::temp_directory_path() / "nnao_bad_radius_term_max.blob").string();
  blob.set_config("radius_term_max", "nan");
  blob.save(path);
  try {
    nnao::NnaoWeights::load(path);
    ADD_FAILURE() << "a NaN ceiling was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("radius_term_max nan out of range 0..100"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

// x^p by squaring: power 8 is the ((x^2)^2)^2 of the first models' blur, to the bit.
TEST(NnaoInference, PowerBySquaringKeepsTheFirstModelsBits) {
  for (float x : {0.0f, 0.137f, 0.5f, 0.73f, 0.999f, 1.0f}) {
    float x8 = x * x;
    x8 *= x8, x8 *= x8;
    EXPECT_EQ(nnao::pow_by_squaring(x, 8, 1.0f), x8) << x;
    EXPECT_EQ(nnao::pow_by_squaring(x, 0, 1.0f), 1.0f) << x;
    EXPECT_EQ(nnao::pow_by_squaring(x, 2, 1.0f), x * x) << x;
    EXPECT_NEAR(nnao::pow_by_squaring(x, 13, 1.0f), std::pow(x, 13.0f), 1e-6f) << x;
  }
}

// blur_depth and blur_normal_power: absent mean the first models' 0.1 and 8; present,
// both the vector and the reference blur use them; out of range the blob is refused.
TEST(NnaoInference, HorizonModelBlursWithTheBlobsEdgeTerms) {
  Blob blob =
      nns::fixtures::spread_nnao_outputs(nns::fixtures::random_nnao_blob(0, 8, 31, false, {8, 8, 4}), 10, -0.3f);
  const auto first = nnao::NnaoWeights::from_blob(blob);
  ASSERT_EQ(first.blur_edges.depth, 0.1f);
  ASSERT_EQ(first.blur_edges.normal_power, 8);
  blob.set_config("blur_passes", 2);
  blob.set_config("blur_depth", 0.3);
  blob.set_config("blur_normal_power", 2);
  const auto m = nnao::NnaoWeights::from_blob(blob);
  ASSERT_EQ(m.blur_edges.depth, 0.3f);
  ASSERT_EQ(m.blur_edges.normal_power, 2);
  const auto view = nns::fixtures::synthetic_view(50, 30, 3, 1);  // g points into it
  auto g = screen_space::gbuffer_from_view(view);
  std::vector<float> raw(size_t(g.pixels())), tmp(raw.size()), expect(raw.size()), got(raw.size()), ref(raw.size()),
      first_terms(raw.size());
  nnao::infer_horizon(m, g, raw.data());
  nnao::bilateral_blur(g, raw.data(), tmp.data(), m.blur_edges);
  nnao::bilateral_blur(g, tmp.data(), expect.data(), m.blur_edges);
  nnao::bilateral_blur(g, raw.data(), tmp.data());
  nnao::bilateral_blur(g, tmp.data(), first_terms.data());
  nnao::infer_exact(m, g, got.data());
  EXPECT_EQ(got, expect);
  int64_t changed = 0;  // the looser terms blur across edges the first ones kept
  for (size_t i = 0; i < got.size(); ++i) changed += std::abs(got[i] - first_terms[i]) > 1e-4f;
  EXPECT_GT(changed, int64_t(got.size() / 20)) << "the edge terms changed too few pixels to be in use";
  nnao::infer_exact_reference(m, g, ref.data());
  expect_close_to_reference(got, ref, "exact, blur depth 0.3, normal power 2");
  for (const char* bad : {"0", "-1", "nan", "1000", "x"}) {
    Blob b = blob;
    b.set_config("blur_depth", bad);
    EXPECT_THROW(nnao::NnaoWeights::from_blob(b), std::runtime_error) << bad;
  }
  for (int bad : {-1, 65}) {
    Blob b = blob;
    b.set_config("blur_normal_power", bad);
    EXPECT_THROW(nnao::NnaoWeights::from_blob(b), std::runtime_error) << bad;
  }
}

TEST(NnaoInference, HorizonBlobWithBadLayoutIsRejected) {
  for (auto [d, s, b] : {std::tuple{8, 8, 3}, std::tuple{0, 8, 4}, std::tuple{8, 100, 4}}) {
    Blob blob = nns::fixtures::random_nnao_blob(0, 4, 3, false, {8, 8, 4});
    blob.set_config("directions", d);
    blob.set_config("steps", s);
    blob.set_config("bands", b);
    EXPECT_THROW(nnao::NnaoWeights::from_blob(blob), std::runtime_error) << d << " " << s << " " << b;
  }
  Blob unknown = nns::fixtures::random_nnao_blob(0, 4, 3, false, {8, 8, 4});
  unknown.set_config("features", std::string("voxels"));
  EXPECT_THROW(nnao::NnaoWeights::from_blob(unknown), std::runtime_error);
}
