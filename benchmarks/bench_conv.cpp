// Conv2d and ConvTranspose2d kernels, forward and forward+backward, on the shapes of
// the thesis's GAN (the pix2pix U-Net and PatchGAN layers at 256x256, k3 s1 layers with 16..512
// channels), with 1 and 2 threads. Names: BM_<Op><Pass>/Cin/Cout/k/stride/pad/HW/threads:T
// for an input of 1 x Cin x HW x HW, so benchmarks/compare can match PyTorch runs.
//
// FLOPs: forward 2*MACs; backward computes the input, weight and bias gradients, so
// forward+backward counts 6*MACs (MACs of one forward pass; a transposed conv has the
// MACs of the convolution it inverts). Counters: FLOP/s and % of the measured FMA peak.
// Before timing, each benchmark compares sampled outputs and gradients of the fast
// kernels with sums computed from the definition (in double).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <map>
#include <string>

#include "benchmarks/fma_peak.h"
#include "core/kernels/conv2d.h"
#include "core/kernels/conv_transpose2d.h"
#include "core/kernels/gemm_precision.h"
#include "core/rng.h"
#include "core/tensor.h"

using namespace nns;

namespace {

double peak_gflops(int threads) {
  static std::map<int, double> cache;
  auto it = cache.find(threads);
  if (it != cache.end()) return it->second;
  return cache[threads] = benchmarks::measure_fma_peak_gflops(threads);
}

Tensor<float> randn(const Shape& s, Rng& rng) {
  Tensor<float> t(s);
  for (auto& v : t) v = float(rng.normal());
  return t;
}

// ---- sampled checks against the definition, in the forward convolution's terms ----
struct Sum {
  double value = 0, magnitude = 0;  // magnitude bounds the rounding error of a float sum
  void add(double a, double b) { value += a * b, magnitude += std::abs(a * b); }
};

// out[n][co][oh][ow] of the convolution (no bias).
Sum conv_out_at(const ConvGeometry& g, const float* x, const float* w, int64_t n, int64_t co, int64_t oh, int64_t ow) {
  Sum s;
  const int64_t grp = co / g.cout_g();
  for (int64_t c = 0; c < g.cin_g(); ++c)
    for (int64_t ki = 0; ki < g.kh; ++ki)
      for (int64_t kj = 0; kj < g.kw; ++kj) {
        int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h, iw = ow * g.stride_w - g.pad_w + kj * g.dil_w;
        if (ih < 0 || ih >= g.H || iw < 0 || iw >= g.W) continue;
        s.add(x[((n * g.C_in + grp * g.cin_g() + c) * g.H + ih) * g.W + iw],
              w[((co * g.cin_g() + c) * g.kh + ki) * g.kw + kj]);
      }
  return s;
}

// d(out)/d(inp) applied to dy at inp[n][ci][ih][iw].
Sum conv_dinp_at(const ConvGeometry& g, const float* dy, const float* w, int64_t n, int64_t ci, int64_t ih,
                 int64_t iw) {
  Sum s;
  const int64_t grp = ci / g.cin_g(), c = ci % g.cin_g();
  for (int64_t co = grp * g.cout_g(); co < (grp + 1) * g.cout_g(); ++co)
    for (int64_t ki = 0; ki < g.kh; ++ki)
      for (int64_t kj = 0; kj < g.kw; ++kj) {
        int64_t th = ih + g.pad_h - ki * g.dil_h, tw = iw + g.pad_w - kj * g.dil_w;
        if (th < 0 || tw < 0 || th % g.stride_h || tw % g.stride_w) continue;
        int64_t oh = th / g.stride_h, ow = tw / g.stride_w;
        if (oh >= g.H_out || ow >= g.W_out) continue;
        s.add(dy[((n * g.C_out + co) * g.H_out + oh) * g.W_out + ow],
              w[((co * g.cin_g() + c) * g.kh + ki) * g.kw + kj]);
      }
  return s;
}

// d(out)/d(weight) applied to dy at weight[co][c][ki][kj].
Sum conv_dweight_at(const ConvGeometry& g, const float* dy, const float* x, int64_t co, int64_t c, int64_t ki,
                    int64_t kj) {
  Sum s;
  const int64_t ci = co / g.cout_g() * g.cin_g() + c;
  for (int64_t n = 0; n < g.N; ++n)
    for (int64_t oh = 0; oh < g.H_out; ++oh)
      for (int64_t ow = 0; ow < g.W_out; ++ow) {
        int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h, iw = ow * g.stride_w - g.pad_w + kj * g.dil_w;
        if (ih < 0 || ih >= g.H || iw < 0 || iw >= g.W) continue;
        s.add(dy[((n * g.C_out + co) * g.H_out + oh) * g.W_out + ow], x[((n * g.C_in + ci) * g.H + ih) * g.W + iw]);
      }
  return s;
}

bool close(float got, const Sum& want) { return std::abs(got - want.value) <= 1e-5 * want.magnitude + 1e-5; }

// Buffers of one layer in the forward convolution's terms: x (conv input), y (conv output).
struct Layer {
  ConvGeometry g;
  Tensor<float> x, w, b, y, dx, dw, db;
  Layer(const ConvGeometry& geom, Rng& rng) : g(geom) {
    x = randn({g.N, g.C_in, g.H, g.W}, rng);
    w = randn({g.C_out, g.cin_g(), g.kh, g.kw}, rng);
    y = randn({g.N, g.C_out, g.H_out, g.W_out}, rng);
    dx = Tensor<float>::zeros(x.shape());
    dw = Tensor<float>::zeros(w.shape());
  }
};

// Checks the fast kernels of a convolution (transposed=false) or of the transposed
// convolution of g at sampled positions. Returns an error message or "".
std::string check(Layer& L, bool transposed, Rng& rng) {
  const ConvGeometry& g = L.g;
  // Conv: y = conv(x); backward from dy=y gives dx, dw. Transposed: x = convT(y);
  // backward from dout=x gives dy (= conv(x)) and dw.
  Tensor<float> out = transposed ? Tensor<float>(L.x.shape()) : Tensor<float>(L.y.shape());
  Tensor<float> dinp = transposed ? Tensor<float>::zeros(L.y.shape()) : Tensor<float>::zeros(L.x.shape());
  Tensor<float> dw = Tensor<float>::zeros(L.w.shape());
  if (!transposed) {
    conv2d_forward(out.data(), L.x.data(), L.w.data(), static_cast<const float*>(nullptr), g);
    conv2d_backward(dinp.data(), dw.data(), static_cast<float*>(nullptr), L.y.data(), L.x.data(), L.w.data(), g);
  } else {
    conv_transpose2d_forward(out.data(), L.y.data(), L.w.data(), static_cast<const float*>(nullptr), g);
    conv_transpose2d_backward(dinp.data(), dw.data(), static_cast<float*>(nullptr), L.x.data(), L.y.data(), L.w.data(),
                              g);
  }
  for (int s = 0; s < 48; ++s) {
    int64_t n = rng.below(g.N);
    // Conv outputs and transposed-conv input gradients are both conv(x)-shaped values.
    int64_t co = rng.below(g.C_out), oh = rng.below(g.H_out), ow = rng.below(g.W_out);
    const Tensor<float>& yv = transposed ? dinp : out;
    const float* xsrc = L.x.data();
    if (!close(yv[((n * g.C_out + co) * g.H_out + oh) * g.W_out + ow], conv_out_at(g, xsrc, L.w.data(), n, co, oh, ow)))
      return transposed ? "input gradient differs from the definition" : "forward differs from the definition";
    int64_t ci = rng.below(g.C_in), ih = rng.below(g.H), iw = rng.below(g.W);
    const Tensor<float>& xv = transposed ? out : dinp;
    if (!close(xv[((n * g.C_in + ci) * g.H + ih) * g.W + iw], conv_dinp_at(g, L.y.data(), L.w.data(), n, ci, ih, iw)))
      return transposed ? "forward differs from the definition" : "input gradient differs from the definition";
    if (s % 4 == 0) {
      int64_t wo = rng.below(g.C_out), wc = rng.below(g.cin_g()), ki = rng.below(g.kh), kj = rng.below(g.kw);
      Sum want = conv_dweight_at(g, L.y.data(), L.x.data(), wo, wc, ki, kj);
      if (!close(dw[((wo * g.cin_g() + wc) * g.kh + ki) * g.kw + kj], want))
        return "weight gradient differs from the definition";
    }
  }
  return "";
}

enum Pass { kForward, kForwardBackward };

void run(benchmark::State& state, bool transposed, Pass pass, Precision precision = Precision::fp32) {
  const int64_t cin = state.range(0), cout = state.range(1), k = state.range(2), s = state.range(3), p = state.range(4),
                hw = state.range(5);
  const int threads = int(state.range(6));
  const double peak = peak_gflops(threads);
  set_num_threads(threads);
  ConvGeometry g = transposed ? conv_transpose2d_geometry(1, cin, hw, hw, cout, k, k, s, s, p, p, 0, 0, 1, 1, 1)
                              : conv2d_geometry(1, cin, hw, hw, cout, k, k, s, s, p, p, 1, 1, 1);
  Rng rng(42);
  Layer L(g, rng);
  // bf16 (gemm_precision.h): operands that are bf16 already, so the check against the
  // definition keeps its fp32 bound; the speed does not depend on the values.
  const ScopedGemmPrecision mode(precision);
  if (precision == Precision::bf16) {
    for (Tensor<float>* t : {&L.x, &L.w, &L.y})
      for (auto& v : *t) v = round_to_bf16(v);
    state.SetLabel(bf16_isa_description());
  }
  std::string err = check(L, transposed, rng);
  if (!err.empty()) {
    state.SkipWithError(err.c_str());
    return;
  }
  // Transposed: input y (g.C_out channels), output x (g.C_in channels), bias per x channel.
  Tensor<float> bias = randn({transposed ? g.C_in : g.C_out}, rng);
  Tensor<float> dbias = Tensor<float>::zeros(bias.shape());
  Tensor<float> out = transposed ? Tensor<float>(L.x.shape()) : Tensor<float>(L.y.shape());
  Tensor<float> dinp = transposed ? Tensor<float>::zeros(L.y.shape()) : Tensor<float>::zeros(L.x.shape());
  const Tensor<float>& in = transposed ? L.y : L.x;
  const Tensor<float>& dout = transposed ? L.x : L.y;  // any tensor of the output's shape
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    if (transposed) {
      conv_transpose2d_forward(out.data(), in.data(), L.w.data(), bias.data(), g);
      if (pass == kForwardBackward)
        conv_transpose2d_backward(dinp.data(), L.dw.data(), dbias.data(), dout.data(), in.data(), L.w.data(), g);
    } else {
      conv2d_forward(out.data(), in.data(), L.w.data(), bias.data(), g);
      if (pass == kForwardBackward)
        conv2d_backward(dinp.data(), L.dw.data(), dbias.data(), dout.data(), in.data(), L.w.data(), g);
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::DoNotOptimize(dinp.data());
    benchmark::ClobberMemory();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double flops = 2.0 * g.macs() * (pass == kForward ? 1 : 3);
  state.counters["FLOP/s"] = benchmark::Counter(flops, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["%peak"] = flops * double(state.iterations()) / seconds * 1e-9 / peak * 100;
}

void BM_Conv2dFwd(benchmark::State& s) { run(s, false, kForward); }
void BM_Conv2dFwdBwd(benchmark::State& s) { run(s, false, kForwardBackward); }
void BM_ConvTranspose2dFwd(benchmark::State& s) { run(s, true, kForward); }
void BM_ConvTranspose2dFwdBwd(benchmark::State& s) { run(s, true, kForwardBackward); }
void BM_Conv2dFwdBwdBf16(benchmark::State& s) { run(s, false, kForwardBackward, Precision::bf16); }
void BM_ConvTranspose2dFwdBwdBf16(benchmark::State& s) { run(s, true, kForwardBackward, Precision::bf16); }

// {Cin, Cout, k, stride, pad, HW}
const std::vector<std::vector<int64_t>> kConvShapes = {
    {64, 128, 4, 2, 1, 128},  // the headline shape; U-Net down 2
    // k3 s1 p1, 16..512 channels, 64 MFLOP-ish each
    {16, 16, 3, 1, 1, 256},
    {32, 32, 3, 1, 1, 128},
    {64, 64, 3, 1, 1, 128},
    {128, 128, 3, 1, 1, 64},
    {256, 256, 3, 1, 1, 32},
    {512, 512, 3, 1, 1, 16},
    // pix2pix U-Net (ngf 64, 12 input channels) down path at 256x256
    {12, 64, 4, 2, 1, 256},
    {128, 256, 4, 2, 1, 64},
    {256, 512, 4, 2, 1, 32},
    {512, 512, 4, 2, 1, 16},
    {512, 512, 4, 2, 1, 8},
    {512, 512, 4, 2, 1, 2},
    // PatchGAN n=3 (15 input channels): stride-1 tail layers
    {15, 64, 4, 2, 1, 256},
    {256, 512, 4, 1, 1, 32},
    {512, 1, 4, 1, 1, 31},
};
const std::vector<std::vector<int64_t>> kConvTransposeShapes = {
    {128, 64, 4, 2, 1, 64},  // the headline shape
    // pix2pix U-Net up path: innermost, 1024-channel skips, outermost
    {512, 512, 4, 2, 1, 1},
    {1024, 512, 4, 2, 1, 4},
    {1024, 512, 4, 2, 1, 8},
    {1024, 256, 4, 2, 1, 16},
    {512, 128, 4, 2, 1, 32},
    {256, 64, 4, 2, 1, 64},
    {128, 3, 4, 2, 1, 128},
};

void shapes(benchmark::internal::Benchmark* b, const std::vector<std::vector<int64_t>>& list) {
  b->ArgNames({"", "", "", "", "", "", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
  for (int threads : {1, 2})
    for (auto a : list) {
      a.push_back(threads);
      b->Args(a);
    }
}

}  // namespace

BENCHMARK(BM_Conv2dFwd)->Apply([](auto* b) { shapes(b, kConvShapes); });
BENCHMARK(BM_Conv2dFwdBwd)->Apply([](auto* b) { shapes(b, kConvShapes); });
BENCHMARK(BM_ConvTranspose2dFwd)->Apply([](auto* b) { shapes(b, kConvTransposeShapes); });
BENCHMARK(BM_ConvTranspose2dFwdBwd)->Apply([](auto* b) { shapes(b, kConvTransposeShapes); });
BENCHMARK(BM_Conv2dFwdBwdBf16)->Apply([](auto* b) { shapes(b, kConvShapes); });
BENCHMARK(BM_ConvTranspose2dFwdBwdBf16)->Apply([](auto* b) { shapes(b, kConvTransposeShapes); });

BENCHMARK_MAIN();
