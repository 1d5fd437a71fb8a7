#pragma once
// The five loops of the BLIS-style SGEMM around one micro-kernel (gemm_arch.h):
//   JC over N in NC blocks -> PC over K in KC blocks (pack B) -> IC over M in MC blocks
//   (pack A) -> JR over NR micro-panels -> IR over MR micro-panels -> micro-kernel.
// This runs one thread's share; gemm.h splits C between threads in whole micro-tiles.
//
// The K blocks depend only on K, and beta is applied on the first one only, so every
// element of C sees the same sequence of FMAs however M and N are cut.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

#include "core/kernels/bf16.h"
#include "core/kernels/gemm_arch.h"
#include "core/kernels/gemm_microkernel_bf16.h"
#include "core/kernels/gemm_pack.h"
#include "core/kernels/gemm_pack_bf16.h"
#include "core/kernels/gemm_precision.h"

namespace nns::gemm_detail {

// Per-thread packing buffers, grown on demand and kept for the thread's lifetime (the
// pool's workers are persistent, so steady-state calls never allocate). Separate
// 64-byte aligned blocks per thread: no false sharing.
struct PackBuffer {
  struct Free {
    void operator()(float* p) const { std::free(p); }
  };
  std::unique_ptr<float, Free> data;
  size_t capacity = 0;  // floats

  float* get(size_t floats) {
    if (floats > capacity) {
      size_t bytes = (floats * sizeof(float) + 63) & ~size_t(63);
      float* p = static_cast<float*>(std::aligned_alloc(64, bytes));
      if (!p) throw std::bad_alloc();
      data.reset(p);
      capacity = bytes / sizeof(float);
    }
    return data.get();
  }
};

// The calling thread's buffer for one kind of packed panel: fp32 A and B, and their bf16
// copies (pair_bf16's layout; a float's worth per word).
enum class Pack { a, b, a_bf16, b_bf16 };
inline PackBuffer& thread_pack(Pack which) {
  thread_local PackBuffer buffers[4];
  return buffers[int(which)];
}

using Bf16KernelFn = void (*)(int64_t, const uint32_t*, const uint32_t*, float*, int64_t, float, float, int, int);

inline Bf16KernelFn bf16_kernel() {
  if (bf16_isa() == Bf16Isa::avx512_bf16) return &Avx512Bf16Kernel<kMR, kNR / 16>::run;
  return &GenericBf16Kernel<kMR, kNR>::run;
}

// Converts the ceil(extent / W) panels of kc steps of W floats at src to pair_bf16's
// layout at dst (ceil(extent / W) * ceil(kc / 2) * W words).
inline void pair_panels_bf16_to(uint32_t* dst, const float* src, int W, int64_t extent, int64_t kc) {
  const int64_t panels = (extent + W - 1) / W, kp = (kc + 1) / 2;
  for (int64_t p = 0; p < panels; ++p) pair_bf16(dst + p * kp * W, src + p * kc * W, W, kc);
}
inline uint32_t* pair_panels_bf16(PackBuffer& buf, const float* src, int W, int64_t extent, int64_t kc) {
  const int64_t panels = (extent + W - 1) / W, kp = (kc + 1) / 2;
  uint32_t* dst = reinterpret_cast<uint32_t*>(buf.get(size_t(panels * kp * W)));
  pair_panels_bf16_to(dst, src, W, extent, kc);
  return dst;
}

// gemm_packed_loops' default for bf16: op(A)'s panels come from packed_a in fp32 and are
// paired to bf16 right there. GemmPackedA passes its own bf16 panels instead.
struct PairPackedA {};

// K is cut into equal blocks of at most kKC so no block is a sliver.
inline int64_t k_block(int64_t K) {
  int64_t nblocks = (K + kKC - 1) / kKC;
  return (K + nblocks - 1) / nblocks;
}

// Whether pack_b can also be called with a uint32_t* destination, packing straight into
// pair_bf16's layout (gemm_pack_bf16.h).
template <class PackB>
inline constexpr bool kPacksBf16 = std::is_invocable_v<PackB&, uint32_t*, int64_t, int64_t, int64_t, int64_t>;

// C[0:M, 0:N] := alpha * op(A) op(B) + beta * C, single-threaded. packed_a(pc, kc, ic, mc)
// returns op(A)[ic : ic+mc, pc : pc+kc] packed (pack_a's layout); pack_b(dst, pc, kc, jc, nc)
// packs op(B)[pc : pc+kc, jc : jc+nc] into dst (pack_b's layout). B is only ever seen
// through pack_b, so it need not exist as a matrix (conv2d_implicit.h packs a
// convolution's column matrix straight from the image).
// With Precision::bf16 the bf16 micro-kernel of bf16_isa() runs on panels in pair_bf16's
// layout: pack_b packs them itself when it takes a uint32_t* destination (kPacksBf16);
// otherwise its fp32 panels are rounded to bf16 pairs (pair_bf16) just after packing,
// while still in cache. Either way the same words, and the loops, blocking and thread
// split are those of fp32, so 1 and 2 threads give the same bits in either mode.
// packed_a_bf16(pc, kc, ic, mc), if given, returns op(A)'s block already in pair_bf16's
// layout (packed_a is then not called in bf16).
template <class PackedA, class PackB, class PackedABf16 = PairPackedA>
void gemm_packed_loops(PackedA&& packed_a, PackB&& pack_b_block, int64_t M, int64_t N, int64_t K, float alpha,
                       float beta, float* C, int64_t ldc, Precision precision = Precision::fp32,
                       PackedABf16 packed_a_bf16 = {}) {
  const bool bf16 = precision == Precision::bf16;
  const Bf16KernelFn bf16_run = bf16 ? bf16_kernel() : nullptr;
  const uint32_t* bbf = nullptr;
  // With a single MC block of rows, each packed B micro-panel is used by one sweep of
  // the IR loop only: packing it just before that sweep keeps it in L1 instead of
  // writing the whole KC x NC block out to L3 and reading it back (-19% time at
  // M = 128, N = 4096, K = 1024). Same micro-kernel calls in the same order either way.
  const bool panel_at_a_time = M <= kMC;
  const int64_t kb = k_block(K);
  const int64_t nc_max = panel_at_a_time ? kNR : std::min<int64_t>(kNC, (N + kNR - 1) / kNR * kNR);
  const bool direct_b = bf16 && kPacksBf16<PackB>;
  float* bpack = direct_b ? nullptr : thread_pack(Pack::b).get(size_t(kb * nc_max));
  uint32_t* bdirect =
      direct_b ? reinterpret_cast<uint32_t*>(thread_pack(Pack::b_bf16).get(size_t((kb + 1) / 2 * nc_max))) : nullptr;
  // op(B)[pc : pc+kc, j : j+n] into pair_bf16's layout at bbf.
  auto pack_b_bf16_block = [&](int64_t pc, int64_t kc, int64_t j, int64_t n) {
    if constexpr (kPacksBf16<PackB>) {
      pack_b_block(bdirect, pc, kc, j, n);
      bbf = bdirect;
    } else {
      pack_b_block(bpack, pc, kc, j, n);
      bbf = pair_panels_bf16(thread_pack(Pack::b_bf16), bpack, kNR, n, kc);
    }
  };
  for (int64_t jc = 0; jc < N; jc += kNC) {
    const int64_t nc = std::min(kNC, N - jc);
    for (int64_t pc = 0; pc < K; pc += kb) {
      const int64_t kc = std::min(kb, K - pc);
      const float beta_block = pc == 0 ? beta : 1.0f;
      const int64_t kp = (kc + 1) / 2;
      if (!panel_at_a_time) {
        if (bf16) pack_b_bf16_block(pc, kc, jc, nc);
        else pack_b_block(bpack, pc, kc, jc, nc);
      }
      for (int64_t ic = 0; ic < M; ic += kMC) {
        const int64_t mc = std::min(kMC, M - ic);
        const float* apack = nullptr;
        const uint32_t* abf = nullptr;
        if constexpr (std::is_same_v<PackedABf16, PairPackedA>) {
          apack = packed_a(pc, kc, ic, mc);
          if (bf16) abf = pair_panels_bf16(thread_pack(Pack::a_bf16), apack, kMR, mc, kc);
        } else if (bf16) {
          abf = packed_a_bf16(pc, kc, ic, mc);
        } else {
          apack = packed_a(pc, kc, ic, mc);
        }
        for (int64_t jr = 0; jr < nc; jr += kNR) {
          const int n = int(std::min<int64_t>(kNR, nc - jr));
          if (panel_at_a_time) {
            if (bf16) pack_b_bf16_block(pc, kc, jc + jr, int64_t(n));
            else pack_b_block(bpack, pc, kc, jc + jr, int64_t(n));
          }
          const float* bp = panel_at_a_time ? bpack : bpack + jr * kc;
          const uint32_t* bpbf = bf16 ? (panel_at_a_time ? bbf : bbf + jr * kp) : nullptr;
          for (int64_t ir = 0; ir < mc; ir += kMR) {
            const int m = int(std::min<int64_t>(kMR, mc - ir));
            float* c = C + (ic + ir) * ldc + jc + jr;
            if (bf16) bf16_run(kp, abf + ir * kp, bpbf, c, ldc, alpha, beta_block, m, n);
            else Kernel::run(kc, apack + ir * kc, bp, c, ldc, alpha, beta_block, m, n);
          }
        }
      }
    }
  }
}

// pack_b for an op(B) held in memory, in fp32 or straight into bf16 pairs.
struct PackerB {
  MatView B;
  void operator()(float* dst, int64_t pc, int64_t kc, int64_t jc, int64_t nc) const {
    pack_b<kNR>(dst, B, pc, kc, jc, nc);
  }
  void operator()(uint32_t* dst, int64_t pc, int64_t kc, int64_t jc, int64_t nc) const {
    pack_b_bf16<kNR>(dst, B, pc, kc, jc, nc);
  }
};
inline PackerB packer_b(const MatView& B) { return PackerB{B}; }

inline void gemm_packed(const MatView& A, const MatView& B, int64_t M, int64_t N, int64_t K, float alpha, float beta,
                        float* C, int64_t ldc, Precision precision = Precision::fp32) {
  const int64_t mc_max = std::min<int64_t>(kMC, (M + kMR - 1) / kMR * kMR);
  const int64_t kb = k_block(K);
  if (precision == Precision::bf16) {
    // op(A) packed straight into bf16 pairs (the same words as pairing pack_a's panels).
    uint32_t* abf = reinterpret_cast<uint32_t*>(thread_pack(Pack::a_bf16).get(size_t((kb + 1) / 2 * mc_max)));
    gemm_packed_loops([](int64_t, int64_t, int64_t, int64_t) -> const float* { return nullptr; }, packer_b(B), M, N, K,
                      alpha, beta, C, ldc, precision,
                      [&](int64_t pc, int64_t kc, int64_t ic, int64_t mc) -> const uint32_t* {
                        pack_a_bf16<kMR>(abf, A, ic, mc, pc, kc);
                        return abf;
                      });
    return;
  }
  float* apack = thread_pack(Pack::a).get(size_t(kb * mc_max));
  gemm_packed_loops(
      [&](int64_t pc, int64_t kc, int64_t ic, int64_t mc) {
        pack_a<kMR>(apack, A, ic, mc, pc, kc);
        return static_cast<const float*>(apack);
      },
      packer_b(B), M, N, K, alpha, beta, C, ldc, precision);
}

}  // namespace nns::gemm_detail
