#pragma once
// The precision of every float GEMM (and so of every convolution, transposed convolution
// and linear layer): fp32 (the default), or bf16 — both operands rounded to bfloat16,
// products summed in fp32 (mixed-precision training, `--precision bf16`). A process-wide
// setting rather than an argument: the trainers set it once for a run, and it must reach
// the GEMMs of every layer without changing the signature of every kernel pair. sgemm
// reads it once per call on the calling thread, so a product never mixes modes.
//
// bf16_isa() is the instruction set the bf16 GEMM runs, chosen from cpuid at run time.
#include <atomic>
#include <stdexcept>
#include <string>

#include "core/kernels/cpu_features.h"

namespace nns {

enum class Precision { fp32, bf16 };

inline const char* precision_name(Precision p) { return p == Precision::bf16 ? "bf16" : "fp32"; }

// The precision a GAN trains in by default (`--precision auto`): bf16 where its GEMM was
// measured faster than fp32's for the default's training and where the validation split
// scores it within fp32's seed spread (docs/results/2026-12-08-gi-bf16-default.md):
// AMD Zen 4 at 0.59-0.82x fp32's loop time over three seeds, Zen 5 about 0.85x. Not on
// the Intel Xeon that was measured (AVX512-BF16 and AMX: bf16 1.26x slower), nor without
// AVX512-BF16 (the generic kernel). So: an AMD CPU with AVX512-BF16.
inline Precision faster_training_precision(const CpuFeatures& f) {
  return f.amd && f.avx512_bf16 ? Precision::bf16 : Precision::fp32;
}

// "fp32", "bf16", or "auto" (faster_training_precision on this CPU); anything else throws
// naming the value.
inline Precision parse_precision(const std::string& s) {
  if (s == "fp32") return Precision::fp32;
  if (s == "bf16") return Precision::bf16;
  if (s == "auto") return faster_training_precision(cpu_features());
  throw std::invalid_argument("precision must be auto, fp32 or bf16, not '" + s + "'");
}

namespace gemm_detail {
inline std::atomic<Precision>& precision_setting() {
  static std::atomic<Precision> p{Precision::fp32};
  return p;
}
inline std::atomic<bool>& bf16_generic_forced() {
  static std::atomic<bool> forced{false};
  return forced;
}
}  // namespace gemm_detail

inline Precision gemm_precision() { return gemm_detail::precision_setting().load(); }
inline void set_gemm_precision(Precision p) { gemm_detail::precision_setting().store(p); }

// Sets the precision for a scope and restores the previous one.
class ScopedGemmPrecision {
 public:
  explicit ScopedGemmPrecision(Precision p) : old_(gemm_precision()) { set_gemm_precision(p); }
  ~ScopedGemmPrecision() { set_gemm_precision(old_); }
  ScopedGemmPrecision(const ScopedGemmPrecision&) = delete;
  ScopedGemmPrecision& operator=(const ScopedGemmPrecision&) = delete;

 private:
  Precision old_;
};

enum class Bf16Isa { avx512_bf16, generic };

// Makes bf16_isa() answer generic whatever the CPU (tests of the fallback path).
inline void force_generic_bf16(bool on) { gemm_detail::bf16_generic_forced().store(on); }

inline Bf16Isa bf16_isa() {
  if (cpu_features().avx512_bf16 && !gemm_detail::bf16_generic_forced().load()) return Bf16Isa::avx512_bf16;
  return Bf16Isa::generic;
}

// What the bf16 GEMM runs on this machine and why, for the trainers and benchmarks.
inline std::string bf16_isa_description() {
  const CpuFeatures& f = cpu_features();
  std::string s =
      bf16_isa() == Bf16Isa::avx512_bf16
          ? "avx512_bf16 (vdpbf16ps)"
          : std::string("generic C++ (fell back: ") + (f.avx512_bf16 ? "forced" : "this CPU has no AVX512-BF16") + ")";
  s += f.amx_bf16 && f.amx_tile ? "; AMX-BF16 present but unused (no AMX kernel yet)" : "; no AMX-BF16";
  return s;
}

}  // namespace nns
