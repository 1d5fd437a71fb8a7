#pragma once
// Implicit-GEMM convolution: the GEMM's B micro-panels are packed straight from the image,
// so im2col's column matrix (kh*kw times the input) is never written out and read back.
// For a 16 -> 16 channel 3x3 layer the GEMM does only 16 multiply-adds per column
// element, and the copy through memory cost as much as the arithmetic.
//
// Column matrix (im2col.h): col[(c*kh + ki)*kw + kj][oh*W_out + ow]
//                           = inp[c][oh*sh - ph + ki*dh][ow - pw + kj*dw]   (stride_w = 1)
// Only stride_w == 1 is packed this way: each k row of a micro-panel is then one or two
// contiguous runs of one input row. Strided layers keep im2col (conv2d.h).
//
// The output is made a block of rows at a time. The input rows a block reads are first
// copied, zero-padded, into a small buffer (PaddedRows): the panel packer then needs no
// bounds checks, and the channels are no longer a power-of-two bytes apart. Read in
// place, the 64 channel planes of a 128 x 128 image all fall into the same L1 and L2
// sets, and the packer ran at a third of the speed.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/kernels/conv_geometry.h"
#include "core/kernels/conv_units.h"
#include "core/kernels/gemm.h"
#include "core/kernels/gemm_pack_bf16.h"
#include "core/tensor.h"
#include "core/thread_pool.h"

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace nns {

// Geometries conv2d_implicit_forward handles. Output rows narrower than a micro-panel
// make every panel straddle rows (two or more masked runs per k): im2col measured faster
// there (512 -> 512 channels at 16 x 16: 171 vs 155 GFLOP/s), and for strided rows too.
inline bool conv_use_implicit(const ConvGeometry& g) {
  return g.stride_w == 1 && g.groups == 1 && !g.is_pointwise() && g.W_out >= gemm_detail::kNR;
}

// The zero-padded input rows [ih0, ih0 + rows) of every channel of one image:
// row r of channel c starts at data + c*chan + r*row, with pad_w zeros either side.
struct PaddedRows {
  int64_t row = 0, chan = 0, rows = 0;

  static PaddedRows layout(const ConvGeometry& g, int64_t rows) {
    PaddedRows p;
    p.rows = rows;
    p.row = g.W + 2 * g.pad_w;
    // +16 floats: consecutive channels must not land a power of two bytes apart.
    p.chan = (rows * p.row + 15) / 16 * 16 + 16;
    return p;
  }
  void fill(float* data, const float* image, const ConvGeometry& g, int64_t ih0) const {
    parallel_for(
        g.C_in,
        [&](int64_t c0, int64_t c1) {
          for (int64_t c = c0; c < c1; ++c)
            for (int64_t r = 0; r < rows; ++r) {
              float* d = data + c * chan + r * row;
              const int64_t ih = ih0 + r;
              if (ih < 0 || ih >= g.H) {
                std::fill(d, d + row, 0.0f);
                continue;
              }
              std::fill(d, d + g.pad_w, 0.0f);
              std::copy(image + (c * g.H + ih) * g.W, image + (c * g.H + ih + 1) * g.W, d + g.pad_w);
              std::fill(d + g.pad_w + g.W, d + row, 0.0f);
            }
        },
        std::max<int64_t>(1, 8192 / std::max<int64_t>(1, rows * row)));
  }
};

// pack_b for GemmPackedA::multiply_packing_b: the column matrix of a block of output rows,
// read from the block's PaddedRows.
class ImplicitColumns {
 public:
  // Offset of column-matrix row k in the padded rows of a block's first output row.
  static std::vector<int64_t> k_offsets(const ConvGeometry& g, const PaddedRows& p) {
    std::vector<int64_t> off(size_t(g.col_rows()));
    for (int64_t k = 0; k < g.col_rows(); ++k) {
      const int64_t c = k / (g.kh * g.kw), ki = k / g.kw % g.kh, kj = k % g.kw;
      off[size_t(k)] = c * p.chan + ki * g.dil_h * p.row + kj * g.dil_w;
    }
    return off;
  }

  ImplicitColumns(const ConvGeometry& g, const PaddedRows& p, const float* rows, const std::vector<int64_t>& k_off)
      : W_out_(g.W_out), step_(g.stride_h * p.row), rows_(rows), k_off_(k_off.data()) {}

  // Packs col[pc : pc+kc][jc : jc+nc] into ceil(nc / NR) panels of NR columns.
  void operator()(float* dst, int64_t pc, int64_t kc, int64_t jc, int64_t nc) const {
    constexpr int NR = gemm_detail::kNR;
    for (int64_t j = jc; j < jc + nc; j += NR, dst += NR * kc)
      pack_panel(dst, pc, kc, j, int(std::min<int64_t>(NR, jc + nc - j)));
  }
  // The same panels in pair_bf16's layout (ceil(kc / 2) steps of NR words), packed straight
  // from the padded rows: the words pair_bf16 gives on the fp32 panels.
  void operator()(uint32_t* dst, int64_t pc, int64_t kc, int64_t jc, int64_t nc) const {
    constexpr int NR = gemm_detail::kNR;
#if defined(__AVX512F__)
    if (gemm_detail::bf16_pack_detail::runs_avx512_bf16()) {
      for (int64_t j = jc; j < jc + nc; j += NR, dst += NR * ((kc + 1) / 2))
        pack_panel_bf16(dst, pc, kc, j, int(std::min<int64_t>(NR, jc + nc - j)));
      return;
    }
#endif
    // Elsewhere (the portable build, CPUs without AVX512-BF16): the fp32 panel, then
    // pair_bf16. (64-byte aligned: pack_panel stores whole aligned vectors.)
    thread_local gemm_detail::PackBuffer buffer;
    float* panel = buffer.get(size_t(NR * kc));
    for (int64_t j = jc; j < jc + nc; j += NR, dst += NR * ((kc + 1) / 2)) {
      pack_panel(panel, pc, kc, j, int(std::min<int64_t>(NR, jc + nc - j)));
      pair_bf16(dst, panel, NR, kc);
    }
  }

 private:
  static constexpr int kNR = gemm_detail::kNR;
  // The panel's columns as runs inside one output row: lanes [lane[r], lane[r+1]) read
  // from rows_ + src[r] + k_off[k] onwards (src[r] is offset by -lane[r]: lane l reads
  // src + l).
  struct Runs {
    int64_t src[kNR];
    int lane[kNR + 1];
    int count = 0;
  };
  Runs runs_of(int64_t j, int n) const {
    Runs r;
    for (int l = 0; l < n; ++r.count) {
      const int64_t oh = (j + l) / W_out_, ow = (j + l) % W_out_;
      r.src[r.count] = oh * step_ + ow - l;
      r.lane[r.count] = l;
      l += int(std::min<int64_t>(n - l, W_out_ - ow));
    }
    r.lane[r.count] = n;
    return r;
  }

#if defined(__AVX512F__)
  static_assert(kNR % 16 == 0, "panels are whole zmm vectors");
  // Lanes [16h, 16h + 16) of column-matrix row k (relative to k_off) when the panel
  // straddles output rows; zero past the panel's n columns.
  __m512 load_runs(const Runs& r, int64_t k_off, int h) const {
    __m512 v = _mm512_setzero_ps();
    for (int i = 0; i < r.count; ++i) {
      const int lo = std::max(r.lane[i], 16 * h), hi = std::min(r.lane[i + 1], 16 * h + 16);
      if (lo >= hi) continue;
      const __mmask16 m = __mmask16(((1u << (hi - 16 * h)) - 1u) & ~((1u << (lo - 16 * h)) - 1u));
      v = _mm512_mask_loadu_ps(v, m, rows_ + r.src[i] + k_off + 16 * h);
    }
    return v;
  }
#endif

  void pack_panel(float* __restrict dst, int64_t pc, int64_t kc, int64_t j, int n) const {
    constexpr int NR = kNR;
    const Runs r = runs_of(j, n);
    const int64_t* k_off = k_off_ + pc;
#if defined(__AVX512F__)
    if (r.count == 1 && n == NR) {  // the common case: one full run
      const float* base = rows_ + r.src[0];
      for (int64_t k = 0; k < kc; ++k, dst += NR)
        for (int h = 0; h < NR / 16; ++h) _mm512_store_ps(dst + 16 * h, _mm512_loadu_ps(base + k_off[k] + 16 * h));
      return;
    }
    for (int64_t k = 0; k < kc; ++k, dst += NR)
      for (int h = 0; h < NR / 16; ++h) _mm512_store_ps(dst + 16 * h, load_runs(r, k_off[k], h));
#else
    for (int64_t k = 0; k < kc; ++k, dst += NR) {
      for (int i = 0; i < r.count; ++i)
        for (int l = r.lane[i]; l < r.lane[i + 1]; ++l) dst[l] = rows_[r.src[i] + k_off[k] + l];
      for (int l = n; l < NR; ++l) dst[l] = 0.0f;
    }
#endif
  }

#if defined(__AVX512F__)
  __attribute__((target("avx512f,avx512bw,avx512bf16"))) void pack_panel_bf16(uint32_t* __restrict dst, int64_t pc,
                                                                              int64_t kc, int64_t j, int n) const {
    constexpr int NR = kNR;
    const int64_t* k_off = k_off_ + pc;
    const Runs r = runs_of(j, n);
    if (r.count == 1 && n == NR) {  // one full run: two rows of the padded input per pair
      const float* base = rows_ + r.src[0];
      for (int64_t k = 0; k < kc; k += 2, dst += NR)
        gemm_detail::bf16_pack_detail::pair_rows_avx512(dst, base + k_off[k],
                                                        k + 1 < kc ? base + k_off[k + 1] : nullptr, NR, NR);
      return;
    }
    for (int64_t k = 0; k < kc; k += 2, dst += NR)
      for (int h = 0; h < NR / 16; ++h) {
        const __m512 hi = k + 1 < kc ? load_runs(r, k_off[k + 1], h) : _mm512_setzero_ps();
        _mm512_store_si512(dst + 16 * h, gemm_detail::bf16_pack_detail::pair_words_fast(load_runs(r, k_off[k], h), hi));
      }
  }
#endif

  int64_t W_out_, step_;
  const float* rows_;
  const int64_t* k_off_;
};

// Input rows read by `rows` consecutive output rows.
inline int64_t implicit_input_rows(const ConvGeometry& g, int64_t rows) {
  return (rows - 1) * g.stride_h + (g.kh - 1) * g.dil_h + 1;
}

// Output rows per block: about kCols GEMM columns, fewer if the padded rows would pass
// kBufferFloats; equal blocks.
inline int64_t implicit_rows_per_block(const ConvGeometry& g) {
  constexpr int64_t kCols = 2048, kBufferFloats = int64_t(1) << 17;
  int64_t rows = std::clamp<int64_t>((kCols + g.W_out - 1) / g.W_out, 1, g.H_out);
  while (rows > 1 && PaddedRows::layout(g, implicit_input_rows(g, rows)).chan * g.C_in > kBufferFloats) --rows;
  const int64_t blocks = (g.H_out + rows - 1) / rows;
  return (g.H_out + blocks - 1) / blocks;
}

// out (+)= conv(inp, weight) + bias: per image and block of output rows,
// out_blk (C_out, cols) = W (C_out, K) * col_blk (K, cols), with W packed once per call.
// Returns false (and does nothing) when the shapes do not take the packed GEMM, or for a
// bias added on top of an accumulating call (no layer does that); the caller then
// lowers with im2col.
inline bool conv2d_implicit_forward(float* out, const float* inp, const float* weight, const float* bias,
                                    const ConvGeometry& g, bool accumulate) {
  if (!conv_use_implicit(g) || (bias && accumulate)) return false;
  const int64_t K = g.col_rows(), P = g.out_plane();
  const int64_t rows = implicit_rows_per_block(g);
  const GemmPackedA w(false, g.C_out, K, weight, K, rows * g.W_out);
  const int64_t last_cols = (g.H_out - (g.H_out - 1) / rows * rows) * g.W_out;
  if (!w.packs_for(rows * g.W_out) || !w.packs_for(last_cols)) return false;
  const PaddedRows layout = PaddedRows::layout(g, implicit_input_rows(g, rows));
  const std::vector<int64_t> k_off = ImplicitColumns::k_offsets(g, layout);
  const int64_t per_image = (g.H_out + rows - 1) / rows;
  for_each_unit<float>(g, g.N * per_image, layout.chan * g.C_in, [&](int64_t u, float* buffer) {
    const int64_t n = u / per_image, oh0 = u % per_image * rows;
    const int64_t oh1 = std::min(g.H_out, oh0 + rows), cols = (oh1 - oh0) * g.W_out;
    layout.fill(buffer, inp + n * g.C_in * g.in_plane(), g, oh0 * g.stride_h - g.pad_h);
    float* y = out + n * g.C_out * P + oh0 * g.W_out;
    // The bias goes in as C with beta = 1: the GEMM adds to it in the same pass.
    if (bias)
      for (int64_t c = 0; c < g.C_out; ++c) std::fill(y + c * P, y + c * P + cols, bias[c]);
    const float beta = accumulate || bias ? 1.0f : 0.0f;
    w.multiply_packing_b(cols, 1.0f, ImplicitColumns(g, layout, buffer, k_off), beta, y, P);
  });
  return true;
}

// dinp (+)= the input gradient of a stride-1 convolution, computed as the convolution it
// is: dout convolved with the weights flipped in space and transposed in channels,
// padded by d(k-1) - p. That is a forward pass, so it goes implicit too (no column matrix
// and no col2im scatter-add). Returns false when that does not apply, or when the
// weights are large (C_out*kh*kw > 2048): copying them flipped then costs more than the
// column matrix saves (PatchGAN's 256 -> 512 4x4 layer: 170 -> 165 GFLOP/s; 16 -> 16 3x3
// at 256 x 256: 84 -> 101).
inline bool conv2d_implicit_backward_input(float* dinp, const float* dout, const float* weight, const ConvGeometry& g,
                                           bool accumulate) {
  constexpr int64_t kMaxFlippedK = 2048;
  if (g.stride_h != 1 || g.stride_w != 1 || g.groups != 1 || g.is_pointwise() || g.C_out * g.kh * g.kw > kMaxFlippedK)
    return false;
  const int64_t ph = g.dil_h * (g.kh - 1) - g.pad_h, pw = g.dil_w * (g.kw - 1) - g.pad_w;
  if (ph < 0 || pw < 0 || g.H != g.H_out + 2 * ph - g.dil_h * (g.kh - 1) ||
      g.W != g.W_out + 2 * pw - g.dil_w * (g.kw - 1))
    return false;
  ConvGeometry t = g;  // the transposed convolution: dout -> dinp
  t.C_in = g.C_out, t.H = g.H_out, t.W = g.W_out, t.C_out = g.C_in;
  t.pad_h = ph, t.pad_w = pw, t.H_out = g.H, t.W_out = g.W;
  Tensor<float> flipped({g.C_in * g.C_out * g.kh * g.kw});
  const int64_t taps = g.kh * g.kw;
  parallel_for(g.C_in, [&](int64_t c0, int64_t c1) {
    for (int64_t c = c0; c < c1; ++c)
      for (int64_t co = 0; co < g.C_out; ++co) {
        const float* src = weight + (co * g.C_in + c) * taps;
        float* dst = flipped.data() + (c * g.C_out + co) * taps;
        for (int64_t i = 0; i < taps; ++i) dst[i] = src[taps - 1 - i];
      }
  });
  return conv2d_implicit_forward(dinp, dout, flipped.data(), nullptr, t, accumulate);
}

}  // namespace nns
