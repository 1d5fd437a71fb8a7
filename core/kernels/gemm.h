#pragma once
// GEMM entry point used by every layer. Row-major:
//   C := alpha * op(A) * op(B) + beta * C   (op = optional transpose)
// beta = 0 assigns (C is not read), beta = 1 accumulates — this is how kernel pairs
// express the gradient contract of core/autograd.h.
//
// float goes (in the precision of gemm_precision.h: fp32, or bf16 inputs with fp32 sums)
// to the packed BLIS-style kernel (gemm_packed.h) unless a direct path fits the
// shape better (gemm_small.h: tiny; gemm_skinny.h: a few columns of C), split between the pool's
// threads in whole micro-tiles of C so that results are bitwise identical for any
// thread count; double (gradient checks) goes to the simple generic loops. The naive
// gemm_reference stays beside them for the tests.
#include <algorithm>
#include <cstdint>
#include <type_traits>

#include "core/allocator.h"
#include "core/kernels/gemm_generic.h"
#include "core/kernels/gemm_packed.h"
#include "core/kernels/gemm_reference.h"
#include "core/kernels/gemm_skinny.h"
#include "core/kernels/gemm_small.h"
#include "core/thread_pool.h"

namespace nns {

namespace gemm_detail {

// Below this many multiply-adds (~10 us on one core) a second thread costs more than
// it saves: waking a worker and waiting for the slower half.
inline constexpr int64_t kParallelMinMacs = int64_t(1) << 20;

inline void scale_c(int64_t M, int64_t N, float beta, float* C, int64_t ldc) {
  for (int64_t i = 0; i < M; ++i)
    for (int64_t j = 0; j < N; ++j) C[i * ldc + j] = beta == 0.0f ? 0.0f : beta * C[i * ldc + j];
}

// Packing one element costs about as much as this many multiply-adds: it is read from
// memory that is usually not in cache, and the micro-kernel does 32 per cycle.
inline constexpr int64_t kPackCostMacs = 16;

// Runs f(m0, m1, n0, n1) on each thread's share of C: the pool's threads split C along
// the dimension that gives the cheaper largest share, counted as its multiply-adds (in
// whole micro-tiles) plus its packing. Each thread packs the whole of the operand along
// the dimension not split: splitting the 64 columns of a 512 x 64 x 8192 product made
// both threads pack all 16 MB of A (0.60x oneDNN). Row shares start on a micro-tile (a
// multiple of kMR), which GemmPackedA relies on.
template <class F>
void split_packed(int64_t M, int64_t N, int64_t K, F&& f) {
  ThreadPool& pool = ThreadPool::global();
  const int nt = pool.threads();
  if (nt == 1 || M * N * K < kParallelMinMacs) return f(int64_t(0), M, int64_t(0), N);
  const int64_t tiles_m = (M + kMR - 1) / kMR, tiles_n = (N + kNR - 1) / kNR;
  const int64_t rows = std::min(M, (tiles_m + nt - 1) / nt * kMR);
  const int64_t cols = std::min(N, (tiles_n + nt - 1) / nt * kNR);
  const int64_t cost_m = rows * N * K + kPackCostMacs * (rows + N) * K;
  const int64_t cost_n = M * cols * K + kPackCostMacs * (M + cols) * K;
  const bool split_n = cost_n <= cost_m;
  pool.run([&](int w, int nw) {
    const int64_t tiles = split_n ? tiles_n : tiles_m, tile = split_n ? kNR : kMR;
    const int64_t extent = split_n ? N : M;
    const int64_t b0 = std::min(extent, tiles * w / nw * tile);
    const int64_t b1 = std::min(extent, tiles * (w + 1) / nw * tile);
    if (b0 >= b1) return;
    if (split_n) f(int64_t(0), M, b0, b1);
    else f(b0, b1, int64_t(0), N);
  });
}

inline bool takes_packed_path(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K);
inline void sgemm_bf16_unpacked(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K, float alpha,
                                const float* A, int64_t lda, const float* B, int64_t ldb, float beta, float* C,
                                int64_t ldc);

inline void sgemm(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K, float alpha, const float* A, int64_t lda,
                  const float* B, int64_t ldb, float beta, float* C, int64_t ldc,
                  Precision precision = gemm_precision()) {
  if (M <= 0 || N <= 0) return;
  if (K <= 0 || alpha == 0.0f) {
    scale_c(M, N, beta, C, ldc);
    return;
  }
  if (precision == Precision::bf16 && !takes_packed_path(trans_a, trans_b, M, N, K))
    return sgemm_bf16_unpacked(trans_a, trans_b, M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
  if (use_gemm_dot(trans_a, trans_b, M, N, K)) return gemm_dot(M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
  if (use_gemm_rows(trans_b, M, N, K)) {
    // Column blocks of 64 are computed independently: any split gives the same bits.
    parallel_for(
        N,
        [&](int64_t j0, int64_t j1) {
          gemm_rows(trans_a, M, j1 - j0, K, alpha, A, lda, B + j0, ldb, beta, C + j0, ldc);
        },
        std::max<int64_t>(64, kParallelMinMacs / std::max<int64_t>(1, M * K)), 64);
    return;
  }
  if (use_gemm_nn_skinny(trans_a, trans_b, M, N, K))
    return gemm_nn_skinny(M, N, K, alpha, A, lda, B, ldb, beta, C, ldc, kParallelMinMacs);
  if (use_gemm_tn_skinny(trans_a, trans_b, M, N, K))
    return gemm_tn_skinny(M, N, K, alpha, A, lda, B, ldb, beta, C, ldc, kParallelMinMacs);
  const MatView a{A, lda, trans_a}, b{B, ldb, trans_b};
  split_packed(M, N, K, [&](int64_t m0, int64_t m1, int64_t n0, int64_t n1) {
    gemm_packed(MatView{a.ptr(m0, 0), lda, trans_a}, MatView{b.ptr(0, n0), ldb, trans_b}, m1 - m0, n1 - n0, K, alpha,
                beta, C + m0 * ldc + n0, ldc, precision);
  });
}

// The shapes sgemm sends to the packed kernel.
inline bool takes_packed_path(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K) {
  return M > 0 && N > 0 && K > 0 && !use_gemm_dot(trans_a, trans_b, M, N, K) && !use_gemm_rows(trans_b, M, N, K) &&
         !use_gemm_nn_skinny(trans_a, trans_b, M, N, K) && !use_gemm_tn_skinny(trans_a, trans_b, M, N, K);
}

// bf16 for the shapes the packed kernel does not take (tiny, or a few columns of C): the
// operands are rounded to bf16 into scratch copies and the fp32 path multiplies them. A
// product of two bf16 is exact in fp32, so this is the same arithmetic as the bf16
// micro-kernels (bf16 inputs, fp32 sums), in another order.
inline void sgemm_bf16_unpacked(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K, float alpha,
                                const float* A, int64_t lda, const float* B, int64_t ldb, float beta, float* C,
                                int64_t ldc) {
  // Stored shapes: A is M x K (K x M transposed), B is K x N (N x K transposed).
  const int64_t a_rows = trans_a ? K : M, a_cols = trans_a ? M : K;
  const int64_t b_rows = trans_b ? N : K, b_cols = trans_b ? K : N;
  CachingAllocator& heap = CachingAllocator::instance();
  // The skinny paths (taken in sgemm's order) stream a large A, a weight matrix, for a few
  // columns of C: they round A themselves (gemm_skinny.h), and only the small B is copied.
  // Same bits as the copies below (the paths' sums do not depend on lda). Copying all of
  // A cost as much as the products: the U-Net's innermost layers took 86 ms per pix2pix
  // iteration in bf16 (41 of them copying) against ~40 in fp32; 38 ms now (1 thread,
  // Ice Lake VM).
  const bool nn_skinny = use_gemm_nn_skinny(trans_a, trans_b, M, N, K);
  if (!use_gemm_dot(trans_a, trans_b, M, N, K) && !use_gemm_rows(trans_b, M, N, K) &&
      (nn_skinny || use_gemm_tn_skinny(trans_a, trans_b, M, N, K))) {
    const size_t b_bytes = size_t(b_rows * b_cols) * sizeof(float);
    float* b = static_cast<float*>(heap.allocate(b_bytes));
    round_copy_bf16(b, B, b_rows, b_cols, ldb);
    if (nn_skinny) gemm_nn_skinny<true>(M, N, K, alpha, A, lda, b, b_cols, beta, C, ldc, kParallelMinMacs);
    else gemm_tn_skinny<true>(M, N, K, alpha, A, lda, b, b_cols, beta, C, ldc, kParallelMinMacs);
    heap.release(b, b_bytes);
    return;
  }
  const size_t a_bytes = size_t(a_rows * a_cols) * sizeof(float);
  const size_t b_bytes = size_t(b_rows * b_cols) * sizeof(float);
  float* a = static_cast<float*>(heap.allocate(a_bytes));
  float* b = static_cast<float*>(heap.allocate(b_bytes));
  parallel_for(a_rows,
               [&](int64_t r0, int64_t r1) { round_copy_bf16(a + r0 * a_cols, A + r0 * lda, r1 - r0, a_cols, lda); });
  parallel_for(b_rows,
               [&](int64_t r0, int64_t r1) { round_copy_bf16(b + r0 * b_cols, B + r0 * ldb, r1 - r0, b_cols, ldb); });
  sgemm(trans_a, trans_b, M, N, K, alpha, a, a_cols, b, b_cols, beta, C, ldc, Precision::fp32);
  heap.release(a, a_bytes);
  heap.release(b, b_bytes);
}

}  // namespace gemm_detail

// op(A) packed once for several products against different B, such as a convolution's
// weights against each block of its rows: gemm() would pack it again for every block.
// multiply() gives the same bits as gemm() with the same operands (same K blocks, same
// micro-kernel, same split between threads). The packing is only done when the product
// shape given to the constructor takes the packed kernel; otherwise multiply() is gemm().
// The products run in the precision set when the object was made (gemm_precision()): in
// bf16 the panels are kept in pair_bf16's layout only, converted once here instead of
// once per product and per thread (the same words gemm_packed_loops would pair), packed
// straight into bf16 pairs (gemm_pack_bf16.h).
class GemmPackedA {
 public:
  GemmPackedA(bool trans_a, int64_t M, int64_t K, const float* A, int64_t lda, int64_t typical_n)
      : trans_a_(trans_a), M_(M), K_(K), A_(A), lda_(lda), precision_(gemm_precision()) {
    using namespace gemm_detail;
    if (!takes_packed_path(trans_a, false, M, typical_n, K) || !takes_packed_path(trans_a, true, M, typical_n, K))
      return;
    kb_ = k_block(K);
    mpad_ = (M + kMR - 1) / kMR * kMR;
    const bool bf16 = precision_ == Precision::bf16;
    const int64_t kblocks = (K + kb_ - 1) / kb_, mblocks = (M + kMC - 1) / kMC;
    // fp32: kc x mpad_ floats per K block; bf16: ceil(kc / 2) x mpad_ words.
    bytes_ = size_t(bf16 ? kblocks * ((kb_ + 1) / 2) * mpad_ : mpad_ * K) * sizeof(float);
    data_ = CachingAllocator::instance().allocate(bytes_);
    // Units = (K block, MC block of rows): the layout gemm_packed_loops reads back.
    const MatView a{A, lda, trans_a};
    parallel_for(kblocks * mblocks, [&](int64_t u0, int64_t u1) {
      for (int64_t u = u0; u < u1; ++u) {
        const int64_t pc = u / mblocks * kb_, ic = u % mblocks * kMC;
        const int64_t kc = std::min(kb_, K - pc), mc = std::min(kMC, M - ic);
        if (!bf16) {
          pack_a<kMR>(fp32_block(pc, kc, ic), a, ic, mc, pc, kc);
          continue;
        }
        pack_a_bf16<kMR>(bf16_block(pc, kc, ic), a, ic, mc, pc, kc);
      }
    });
  }
  ~GemmPackedA() {
    if (data_) CachingAllocator::instance().release(data_, bytes_);
  }
  GemmPackedA(const GemmPackedA&) = delete;
  GemmPackedA& operator=(const GemmPackedA&) = delete;

  // C (M x N) := alpha * op(A) * op(B) + beta * C.
  void multiply(bool trans_b, int64_t N, float alpha, const float* B, int64_t ldb, float beta, float* C,
                int64_t ldc) const {
    using namespace gemm_detail;
    if (!data_ || alpha == 0.0f || !takes_packed_path(trans_a_, trans_b, M_, N, K_))
      return sgemm(trans_a_, trans_b, M_, N, K_, alpha, A_, lda_, B, ldb, beta, C, ldc, precision_);
    multiply_packing_b(N, alpha, packer_b(MatView{B, ldb, trans_b}), beta, C, ldc);
  }

  // Whether multiply_packing_b can be used for products with N columns.
  bool packs_for(int64_t N) const { return data_ && gemm_detail::takes_packed_path(trans_a_, false, M_, N, K_); }

  // The same product with a B that exists only through pack_b(dst, pc, kc, jc, nc), which
  // packs op(B)[pc : pc+kc, jc : jc+nc] (gemm_pack.h's layout). Needs packs_for(N).
  template <class PackB>
  void multiply_packing_b(int64_t N, float alpha, PackB&& pack_b, float beta, float* C, int64_t ldc) const {
    using namespace gemm_detail;
    split_packed(M_, N, K_, [&](int64_t m0, int64_t m1, int64_t n0, int64_t n1) {
      // fp32 panels, or bf16 pairs when pack_b packs those (gemm_detail::kPacksBf16).
      auto pack_b_block = [&](auto* dst, int64_t pc, int64_t kc, int64_t jc,
                              int64_t nc) -> decltype(pack_b(dst, pc, kc, jc, nc)) {
        return pack_b(dst, pc, kc, n0 + jc, nc);
      };
      auto* c = C + m0 * ldc + n0;
      if (precision_ == Precision::bf16)
        gemm_packed_loops([](int64_t, int64_t, int64_t, int64_t) -> const float* { return nullptr; }, pack_b_block,
                          m1 - m0, n1 - n0, K_, alpha, beta, c, ldc, precision_,
                          [&](int64_t pc, int64_t kc, int64_t ic, int64_t) -> const uint32_t* {
                            return bf16_block(pc, kc, m0 + ic);
                          });
      else
        gemm_packed_loops(
            [&](int64_t pc, int64_t kc, int64_t ic, int64_t) -> const float* { return fp32_block(pc, kc, m0 + ic); },
            pack_b_block, m1 - m0, n1 - n0, K_, alpha, beta, c, ldc, precision_);
    });
  }

 private:
  // Rows [ic, ...) of the K block starting at pc (kc deep), a multiple of kMR rows in.
  float* fp32_block(int64_t pc, int64_t kc, int64_t ic) const {
    return static_cast<float*>(data_) + pc * mpad_ + ic * kc;
  }
  uint32_t* bf16_block(int64_t pc, int64_t kc, int64_t ic) const {
    return static_cast<uint32_t*>(data_) + pc / kb_ * ((kb_ + 1) / 2) * mpad_ + ic * ((kc + 1) / 2);
  }

  bool trans_a_;
  int64_t M_, K_;
  const float* A_;
  int64_t lda_;
  Precision precision_;
  int64_t kb_ = 0, mpad_ = 0;
  void* data_ = nullptr;
  size_t bytes_ = 0;
};

template <class T>
void gemm(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K, T alpha, const T* A, int64_t lda, const T* B,
          int64_t ldb, T beta, T* C, int64_t ldc) {
  if constexpr (std::is_same_v<T, float>)
    gemm_detail::sgemm(trans_a, trans_b, M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
  else gemm_detail::gemm_generic(trans_a, trans_b, M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
}

}  // namespace nns
