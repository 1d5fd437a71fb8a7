#pragma once
// 2-d convolution as a pair of kernels, lowered to GEMM (im2col + gemm per block of
// output rows, reusing one column buffer), with PyTorch's semantics and shapes:
//   inp    (N, C_in, H, W)
//   weight (C_out, C_in/groups, kh, kw)      = per group a (C_out/g) x K matrix, K = C_in/g*kh*kw
//   bias   (C_out) or null
//   out    (N, C_out, H_out, W_out),  H_out = (H + 2p - d(k-1) - 1)/s + 1
// Per image, group and row block:  out_blk (C_out/g, R*W_out) = W_g (C_out/g, K) * col (K, R*W_out).
// 1x1 stride-1 unpadded convolutions skip im2col: the input already is the column matrix.
// Layers with at most kConvDirectMaxCout output channels per group skip GEMM altogether
// (core/kernels/conv2d_direct.h). Stride-1 layers with output rows at least a GEMM
// micro-panel wide skip im2col: the GEMM packs its B panels from the input rows
// (core/kernels/conv2d_implicit.h), and their input gradient runs as that forward pass
// with the weights flipped.
//
// The three passes are separate functions because conv_transpose2d (the same
// convolution run backwards) reuses them with the roles of input and output swapped.
// Threads: GEMM splits its own work; im2col/col2im/bias split over rows or channels.
// Every reduction runs in an order fixed by the shapes, so 1 and 2 threads agree bitwise.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/kernels/conv2d_direct.h"
#include "core/kernels/conv2d_implicit.h"
#include "core/kernels/conv_units.h"
#include "core/kernels/conv_geometry.h"
#include "core/kernels/gemm.h"
#include "core/kernels/im2col.h"
#include "core/tensor.h"
#include "core/thread_pool.h"

namespace nns {

// Geometry of Conv2d with PyTorch's output size; throws on bad arguments.
inline ConvGeometry conv2d_geometry(int64_t N, int64_t C_in, int64_t H, int64_t W, int64_t C_out, int64_t kh,
                                    int64_t kw, int64_t stride_h, int64_t stride_w, int64_t pad_h, int64_t pad_w,
                                    int64_t dil_h, int64_t dil_w, int64_t groups) {
  ConvGeometry g;
  g.N = N, g.C_in = C_in, g.H = H, g.W = W, g.C_out = C_out, g.kh = kh, g.kw = kw;
  g.stride_h = stride_h, g.stride_w = stride_w, g.pad_h = pad_h, g.pad_w = pad_w;
  g.dil_h = dil_h, g.dil_w = dil_w, g.groups = groups;
  validate(g, "conv2d");
  return g;
}

// Output rows lowered at once. Two pulls: the GEMM wants at least kMinCols columns
// (narrower products waste its packing and edge tiles), the caches want the column buffer
// near kColBudget elements (512 KB of floats: with the GEMM's packed panels it then
// stays in L2/L3). The buffer never holds more than one image's rows.
inline int64_t conv_rows_per_block(const ConvGeometry& g) {
  constexpr int64_t kColBudget = int64_t(1) << 17, kMinCols = 512;
  const int64_t per_row = g.col_rows() * g.W_out;
  const int64_t rows =
      std::clamp<int64_t>(std::max(kColBudget / per_row, (kMinCols + g.W_out - 1) / g.W_out), 1, g.H_out);
  const int64_t blocks = (g.H_out + rows - 1) / rows;
  return (g.H_out + blocks - 1) / blocks;  // equal blocks: no ragged last one
}

// out[n][c][:] += bias[c] for an (N, C, plane) tensor.
template <class T>
void add_channel_bias(T* out, const T* bias, int64_t N, int64_t C, int64_t plane) {
  parallel_for(
      N * C,
      [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
          T* o = out + i * plane;
          const T v = bias[i % C];
          for (int64_t j = 0; j < plane; ++j) o[j] += v;
        }
      },
      std::max<int64_t>(1, 16384 / std::max<int64_t>(1, plane)));
}

// dbias[c] += sum over n and the plane of dout[n][c][:], per channel in a fixed order
// (8 running partial sums so it vectorizes without -ffast-math).
template <class T>
void channel_sum_add(T* dbias, const T* dout, int64_t N, int64_t C, int64_t plane) {
  parallel_for(
      C,
      [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
          T part[8] = {};
          T tail = 0;
          for (int64_t n = 0; n < N; ++n) {
            const T* d = dout + (n * C + c) * plane;
            int64_t j = 0;
            for (; j + 8 <= plane; j += 8)
              for (int l = 0; l < 8; ++l) part[l] += d[j + l];
            for (; j < plane; ++j) tail += d[j];
          }
          T s = tail;
          for (int l = 0; l < 8; ++l) s += part[l];
          dbias[c] += s;
        }
      },
      std::max<int64_t>(1, 16384 / std::max<int64_t>(1, N * plane)));
}

// A unit of work: image n, group grp, output rows [oh0, oh1). A pointwise convolution
// has one block per image and group (it needs no column buffer).
struct ConvBlock {
  int64_t n, grp, oh0, oh1;
};
struct ConvBlocks {
  int64_t rows, per_image, count;  // rows per block, blocks per (image, group), total
  explicit ConvBlocks(const ConvGeometry& g)
      : rows(g.is_pointwise() ? g.H_out : conv_rows_per_block(g)),
        per_image((g.H_out + rows - 1) / rows),
        count(g.N * g.groups * per_image) {}
  // Units are ordered group-major, then image, then rows.
  ConvBlock operator()(const ConvGeometry& g, int64_t u) const {
    const int64_t grp = u / (g.N * per_image), r = u % (g.N * per_image);
    const int64_t oh0 = r % per_image * rows;
    return {r / per_image, grp, oh0, std::min(g.H_out, oh0 + rows)};
  }
  int64_t col_elems(const ConvGeometry& g) const { return g.is_pointwise() ? 0 : g.col_rows() * rows * g.W_out; }
};

// The column matrix of block b: im2col into `col`, or the input itself when pointwise.
// Returns the matrix and its leading dimension.
template <class T>
const T* lower_block(T* col, const T* inp, const ConvGeometry& g, const ConvBlock& b, int64_t& ld) {
  const T* x = inp + (b.n * g.C_in + b.grp * g.cin_g()) * g.in_plane();
  if (g.is_pointwise()) {
    ld = g.in_plane();
    return x + b.oh0 * g.W;
  }
  im2col(col, x, g, b.oh0, b.oh1);
  ld = (b.oh1 - b.oh0) * g.W_out;
  return col;
}

// Runs f(block, col) over the blocks units[0..n) (all blocks when units is null), each
// thread with its own column buffer (for_each_unit, core/kernels/conv_units.h).
template <class T, class F>
void for_each_block(const ConvGeometry& g, const ConvBlocks& blocks, const int64_t* units, int64_t n, F&& f) {
  for_each_unit<T>(g, n, blocks.col_elems(g), [&](int64_t i, T* col) { f(blocks(g, units ? units[i] : i), col); });
}
template <class T, class F>
void for_each_block(const ConvGeometry& g, const ConvBlocks& blocks, F&& f) {
  for_each_block<T>(g, blocks, nullptr, blocks.count, std::forward<F>(f));
}

// op(W_g) * B for the row blocks of one call: with several blocks and one group the
// float weights are packed once (GemmPackedA) instead of once per block, same bits.
//   op(W_g) (M x K) = W_g (cog x K) or its transpose; W_g starts at weight + grp*cog*K.
template <class T>
class WeightGemm {
 public:
  WeightGemm(const ConvGeometry& g, const ConvBlocks& blocks, bool transposed, const T* weight, int64_t M, int64_t K,
             int64_t ldw)
      : trans_(transposed), M_(M), K_(K), ld_(ldw), group_stride_(g.cout_g() * g.col_rows()), weight_(weight) {
    if constexpr (std::is_same_v<T, float>)
      if (g.groups == 1 && blocks.count > 1)
        packed_ = std::make_unique<GemmPackedA>(transposed, M, K, weight, ldw, blocks.rows * g.W_out);
  }
  // C (M x N) := op(W_grp) * B + beta * C.
  void operator()(int64_t grp, int64_t N, const T* B, int64_t ldb, T beta, T* C, int64_t ldc) const {
    if constexpr (std::is_same_v<T, float>)
      if (packed_) return packed_->multiply(false, N, 1.0f, B, ldb, beta, C, ldc);
    gemm<T>(trans_, false, M_, N, K_, T(1), weight_ + grp * group_stride_, ld_, B, ldb, beta, C, ldc);
  }

 private:
  bool trans_;
  int64_t M_, K_, ld_, group_stride_;
  const T* weight_;
  std::unique_ptr<GemmPackedA> packed_;
};

// out = conv(inp, weight) (+ bias), or out += conv(inp, weight) when accumulate.
// Per block: out_blk (C_out/g, cols) = W_g (C_out/g, K) * col (K, cols).
template <class T>
void conv2d_gemm_forward(T* out, const T* inp, const T* weight, const T* bias, const ConvGeometry& g, bool accumulate) {
  if (conv_use_direct(g)) return conv2d_direct_forward(out, inp, weight, bias, g, accumulate);
  if constexpr (std::is_same_v<T, float>)
    if (conv2d_implicit_forward(out, inp, weight, bias, g, accumulate)) return;
  const int64_t K = g.col_rows(), cog = g.cout_g(), P = g.out_plane();
  const T beta = accumulate ? T(1) : T(0);
  const ConvBlocks blocks(g);
  const WeightGemm<T> wg(g, blocks, /*transposed=*/false, weight, cog, K, K);
  for_each_block<T>(g, blocks, [&](const ConvBlock& b, T* colbuf) {
    int64_t cols;
    const T* col = lower_block(colbuf, inp, g, b, cols);
    T* y = out + (b.n * g.C_out + b.grp * cog) * P + b.oh0 * g.W_out;
    const int64_t ncols = (b.oh1 - b.oh0) * g.W_out;
    wg(b.grp, ncols, col, cols, beta, y, P);
    // The bias goes in while this block of the output is still in cache.
    if (bias)
      parallel_for(
          cog,
          [&](int64_t c0, int64_t c1) {
            for (int64_t c = c0; c < c1; ++c) {
              const T v = bias[b.grp * cog + c];
              for (int64_t j = 0; j < ncols; ++j) y[c * P + j] += v;
            }
          },
          std::max<int64_t>(1, 16384 / ncols));
  });
}

// dweight += dout (x) im2col(inp), per group: dW_g (C_out/g, K) += sum over blocks of
// dout_blk (C_out/g, cols) * col^T. The sum over blocks is a reduction, so its order is
// fixed by the shape alone: with enough blocks, kChunks fixed chunks of blocks are
// summed separately (chunk 0 into dW, the others into scratch) and then added in chunk
// order; whatever the thread count, the result is the same.
template <class T>
void conv2d_backward_weight(T* dweight, const T* dout, const T* inp, const ConvGeometry& g) {
  if (conv_use_direct(g)) return conv2d_direct_backward_weight(dweight, dout, inp, g);
  const int64_t K = g.col_rows(), cog = g.cout_g(), P = g.out_plane();
  const ConvBlocks blocks(g);
  const int64_t per_group = g.N * blocks.per_image, wg = cog * K;
  constexpr int64_t kChunks = 2;
  // Scratch costs one weight-sized buffer per extra chunk: only for weights up to 16 MB.
  const bool chunked = per_group >= 2 * kChunks && wg * g.groups <= (int64_t(1) << 22);
  auto add_block = [&](const ConvBlock& b, T* colbuf, T* dw, T beta) {
    int64_t cols;
    const T* col = lower_block(colbuf, inp, g, b, cols);
    const T* dy = dout + (b.n * g.C_out + b.grp * cog) * P + b.oh0 * g.W_out;
    gemm<T>(false, true, cog, K, (b.oh1 - b.oh0) * g.W_out, T(1), dy, P, col, cols, beta, dw, K);
  };
  if (!chunked) {
    Tensor<T> col({blocks.col_elems(g)});
    for (int64_t u = 0; u < blocks.count; ++u) {
      const ConvBlock b = blocks(g, u);
      add_block(b, col.data(), dweight + b.grp * wg, T(1));
    }
    return;
  }
  Tensor<T> scratch({(kChunks - 1) * g.groups * wg});
  // Job j = (group, chunk); a chunk is a contiguous run of that group's blocks.
  const int64_t jobs = g.groups * kChunks;
  parallel_for(
      jobs,
      [&](int64_t j0, int64_t j1) {
        Tensor<T> col({blocks.col_elems(g)});
        for (int64_t j = j0; j < j1; ++j) {
          const int64_t grp = j / kChunks, c = j % kChunks;
          T* dw = c == 0 ? dweight + grp * wg : scratch.data() + ((c - 1) * g.groups + grp) * wg;
          const int64_t u0 = per_group * c / kChunks, u1 = per_group * (c + 1) / kChunks;
          for (int64_t u = u0; u < u1; ++u)
            add_block(blocks(g, grp * per_group + u), col.data(), dw, c == 0 || u > u0 ? T(1) : T(0));
        }
      },
      g.macs() < double(1 << 18) ? jobs : 1);  // small convolutions stay on one thread
  parallel_for(
      g.groups * wg,
      [&](int64_t i0, int64_t i1) {
        for (int64_t c = 1; c < kChunks; ++c) {
          const T* s = scratch.data() + (c - 1) * g.groups * wg;
          for (int64_t i = i0; i < i1; ++i) dweight[i] += s[i];
        }
      },
      8192);
}

// dinp += col2im(W^T dout) (or dinp = ... when !accumulate): the input-gradient pass,
// which is also conv_transpose2d's forward. Per block: dcol (K, cols) = W_g^T * dout_blk,
// then col2im adds it into dinp.
// Adjacent row blocks add into a few shared input rows, so blocks run in two phases,
// even blocks then odd ones; within a phase no two blocks touch the same row (checked
// below) and every input element receives its sums in an order fixed by the shape.
template <class T>
void conv2d_backward_input(T* dinp, const T* dout, const T* weight, const ConvGeometry& g, bool accumulate = true) {
  if (conv_use_direct(g)) return conv2d_direct_backward_input(dinp, dout, weight, g, accumulate);
  if constexpr (std::is_same_v<T, float>)
    if (conv2d_implicit_backward_input(dinp, dout, weight, g, accumulate)) return;
  const int64_t K = g.col_rows(), cog = g.cout_g(), cig = g.cin_g(), P = g.out_plane();
  if (g.is_pointwise()) {
    for_each_block<T>(g, ConvBlocks(g), [&](const ConvBlock& b, T*) {
      gemm<T>(true, false, cig, P, cog, T(1), weight + b.grp * cog * K, K, dout + (b.n * g.C_out + b.grp * cog) * P, P,
              accumulate ? T(1) : T(0), dinp + (b.n * g.C_in + b.grp * cig) * P, P);
    });
    return;
  }
  if (!accumulate) {
    const int64_t total = g.N * g.C_in * g.in_plane();
    parallel_for(
        total, [&](int64_t b, int64_t e) { std::fill(dinp + b, dinp + e, T(0)); }, 65536);
  }
  const ConvBlocks blocks(g);
  const WeightGemm<T> wg(g, blocks, /*transposed=*/true, weight, K, cog, K);
  auto add_block = [&](const ConvBlock& b, T* dcol) {
    const int64_t cols = (b.oh1 - b.oh0) * g.W_out;
    wg(b.grp, cols, dout + (b.n * g.C_out + b.grp * cog) * P + b.oh0 * g.W_out, P, T(0), dcol, cols);
    col2im_add(dinp + (b.n * g.C_in + b.grp * cig) * g.in_plane(), dcol, g, b.oh0, b.oh1);
  };
  // Block i writes input rows [oh0*s - p, (oh1-1)*s - p + d(k-1)]; blocks i and i+2 are
  // disjoint when d(k-1) < (rows+1)*s.
  const bool phased = blocks.per_image == 1 || g.dil_h * (g.kh - 1) < (blocks.rows + 1) * g.stride_h;
  if (!phased) {
    Tensor<T> dcol({blocks.col_elems(g)});
    for (int64_t u = 0; u < blocks.count; ++u) add_block(blocks(g, u), dcol.data());
    return;
  }
  std::vector<int64_t> units;
  units.reserve(size_t(blocks.count));
  for (int64_t parity = 0; parity < 2; ++parity) {
    units.clear();
    for (int64_t u = 0; u < blocks.count; ++u)
      if (u % blocks.per_image % 2 == parity) units.push_back(u);
    for_each_block<T>(g, blocks, units.data(), int64_t(units.size()), add_block);
  }
}

// ---- the kernel pair -------------------------------------------------------------

// out (N, C_out, H_out, W_out) is assigned; bias may be null.
template <class T>
void conv2d_forward(T* out, const T* inp, const T* weight, const T* bias, const ConvGeometry& g) {
  conv2d_gemm_forward(out, inp, weight, bias, g, /*accumulate=*/false);
}

// Accumulates into dinp, dweight, dbias (the gradient contract); any may be null.
template <class T>
void conv2d_backward(T* dinp, T* dweight, T* dbias, const T* dout, const T* inp, const T* weight,
                     const ConvGeometry& g) {
  if (dbias) channel_sum_add(dbias, dout, g.N, g.C_out, g.out_plane());
  if (dweight) conv2d_backward_weight(dweight, dout, inp, g);
  if (dinp) conv2d_backward_input(dinp, dout, weight, g);
}

}  // namespace nns
