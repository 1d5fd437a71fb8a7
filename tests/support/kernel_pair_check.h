#pragma once
// Runs a fast forward/backward kernel pair and its naive reference on the same random
// buffers, so a test can compare them (or compare 1 thread against 2). The pair's
// contract is the project's: forward assigns every output element, backward accumulates.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/kernels/bf16.h"
#include "core/rng.h"
#include "core/tensor.h"

namespace nns::testing {

// Input x, weight w, bias b and output gradient dy of one layer call.
struct LayerBuffers {
  Tensor<float> x, w, b, dy;
};

inline Tensor<float> randn_float(const Shape& s, Rng& rng) {
  Tensor<float> t(s);
  for (auto& v : t) v = float(rng.normal());
  return t;
}

inline LayerBuffers random_layer_buffers(const Shape& x, const Shape& w, const Shape& b, const Shape& y, Rng& rng) {
  LayerBuffers in;
  in.x = randn_float(x, rng);
  in.w = randn_float(w, rng);
  in.b = randn_float(b, rng);
  in.dy = randn_float(y, rng);
  return in;
}

// {y, dx, dw, db} in T. The output starts as NaN (forward must assign it); the gradients
// start non-zero (backward must add to them). fwd(y, x, w, b); bwd(dx, dw, db, dy, x, w).
// Naive references run in double (forward_backward<double>): their long float sums
// would carry more rounding than the blocked fast kernels they check, and on the portable
// build a 16384-term weight gradient already differed by 1.06e-4 between two float runs.
template <class T = float, class Fwd, class Bwd>
std::array<Tensor<T>, 4> forward_backward(const LayerBuffers& in, Fwd fwd, Bwd bwd) {
  const Tensor<T> x = in.x.cast<T>(), w = in.w.cast<T>(), b = in.b.cast<T>(), dy = in.dy.cast<T>();
  Tensor<T> y(in.dy.shape());
  y.fill(T(NAN));
  fwd(y.data(), x.data(), w.data(), b.data());
  auto dx = Tensor<T>::full(in.x.shape(), T(0.25));
  auto dw = Tensor<T>::full(in.w.shape(), T(-0.5));
  auto db = Tensor<T>::full(in.b.shape(), T(1));
  bwd(dx.data(), dw.data(), db.data(), dy.data(), x.data(), w.data());
  return {std::move(y), std::move(dx), std::move(dw), std::move(db)};
}

// The buffers with x, w and dy rounded to bf16: the operands of a layer's three products
// (forward, input and weight gradients) as Precision::bf16 feeds them to the GEMM. The
// bias and the bias gradient (a sum of dy) stay fp32, so only {y, dx, dw} compare.
inline LayerBuffers bf16_operands(const LayerBuffers& in) {
  LayerBuffers r{in.x.clone(), in.w.clone(), in.b.clone(), in.dy.clone()};
  for (Tensor<float>* t : {&r.x, &r.w, &r.dy})
    for (auto& v : *t) v = round_to_bf16(v);
  return r;
}

inline constexpr const char* kLayerOutputNames[4] = {"forward", "dinp", "dweight", "dbias"};

template <class R>
void expect_close(const Tensor<float>& a, const Tensor<R>& ref, const char* what) {
  ASSERT_EQ(a.shape(), ref.shape()) << what;
  double worst = 0;
  for (int64_t i = 0; i < a.numel(); ++i)
    worst = std::max(worst, std::abs(double(a[i]) - ref[i]) / (1.0 + std::abs(double(ref[i]))));
  EXPECT_LT(worst, 1e-4) << what;
}

template <class R>
void expect_close(const std::array<Tensor<float>, 4>& fast, const std::array<Tensor<R>, 4>& reference) {
  for (int i = 0; i < 4; ++i) expect_close(fast[i], reference[i], kLayerOutputNames[i]);
}

// fast = {y, dx, dw, db} of a fast pair run in Precision::bf16 on in: its products take
// in's x, w and dy rounded to bf16, so {y, dx, dw} are the double reference's on those
// rounded operands, up to fp32 summation (unrounded operands would be ~1e-2 off).
template <class Fwd, class Bwd>
void expect_bf16_matches_reference(const std::array<Tensor<float>, 4>& fast, const LayerBuffers& in, Fwd reference_fwd,
                                   Bwd reference_bwd) {
  const auto ref = forward_backward<double>(bf16_operands(in), reference_fwd, reference_bwd);
  for (int k = 0; k < 3; ++k) expect_close(fast[k], ref[k], kLayerOutputNames[k]);
}

inline bool bitwise_equal(const Tensor<float>& a, const Tensor<float>& b) {
  return a.numel() == b.numel() && std::memcmp(a.data(), b.data(), sizeof(float) * a.numel()) == 0;
}

// run_all(rng) returns one {y, dx, dw, db} per case. It runs with 1 thread, then with 2,
// from the same seed: the results must be the same bits (DEVELOPERS.md, determinism).
template <class RunAll>
void expect_same_bits_on_1_and_2_threads(uint64_t seed, RunAll run_all) {
  std::vector<std::array<Tensor<float>, 4>> res[2];
  for (int t = 0; t < 2; ++t) {
    set_num_threads(t + 1);
    Rng rng(seed);
    res[t] = run_all(rng);
  }
  ASSERT_EQ(res[0].size(), res[1].size());
  for (size_t i = 0; i < res[0].size(); ++i)
    for (int k = 0; k < 4; ++k)
      EXPECT_TRUE(bitwise_equal(res[0][i][k], res[1][i][k])) << "case " << i << " " << kLayerOutputNames[k];
}

}  // namespace nns::testing
