#pragma once
// Which SGEMM micro-kernel this build uses, and the cache blocking around it.
// Chosen at build time from the compiler's target flags: -march=native on this machine
// (Zen 5) gives AVX-512; a portable -march=x86-64 build gets the generic kernel.
//
// Blocking (BLIS terms): a KC x NR micro-panel of B stays in L1 while the IR loop
// streams MR x KC micro-panels of A through it; the MC x KC block of A lives in L2
// (1 MiB per core on Zen 5); the KC x NC block of B in L3.
#include <cstdint>

#if defined(__AVX512F__)
#include "core/kernels/gemm_microkernel_avx512.h"
#elif defined(__AVX2__) && defined(__FMA__)
#include "core/kernels/gemm_microkernel_avx2.h"
#else
#include "core/kernels/gemm_microkernel_generic.h"
#endif

namespace nns::gemm_detail {

// NNS_GEMM_* macros override the tuned values, for tuning experiments only.
#if defined(__AVX512F__)
#ifndef NNS_GEMM_MR
#define NNS_GEMM_MR 14
#endif
#ifndef NNS_GEMM_NV
#define NNS_GEMM_NV 2
#endif
#ifndef NNS_GEMM_KC
#define NNS_GEMM_KC 256
#endif
#ifndef NNS_GEMM_MC
#define NNS_GEMM_MC (NNS_GEMM_MR * 24)
#endif
#ifndef NNS_GEMM_NC
#define NNS_GEMM_NC 3072
#endif
using Kernel = Avx512Kernel<NNS_GEMM_MR, NNS_GEMM_NV>;
inline constexpr const char* kKernelName = "avx512";
inline constexpr int64_t kKC = NNS_GEMM_KC, kMC = NNS_GEMM_MC, kNC = NNS_GEMM_NC;
#elif defined(__AVX2__) && defined(__FMA__)
using Kernel = Avx2Kernel<6, 2>;
inline constexpr const char* kKernelName = "avx2 6x16";
inline constexpr int64_t kKC = 256, kMC = 6 * 24, kNC = 2048;
#else
using Kernel = GenericKernel<4, 16>;
inline constexpr const char* kKernelName = "generic 4x16";
inline constexpr int64_t kKC = 256, kMC = 4 * 32, kNC = 1024;
#endif

inline constexpr int kMR = Kernel::mr;
inline constexpr int kNR = Kernel::nr;

}  // namespace nns::gemm_detail
