// SGEMM yardstick: times the same row-major shapes as build/benchmarks/bench_gemm in
// OpenBLAS (-DYARDSTICK_OPENBLAS, cblas_sgemm) or oneDNN (-DYARDSTICK_ONEDNN,
// dnnl_sgemm), and bf16 GEMM (bench_gemm's BM_GemmBf16) in oneDNN's matmul primitive
// with bf16 source and weights and an fp32 destination (-DYARDSTICK_ONEDNN_BF16: Debian's
// oneDNN 2.6 has no public bf16 GEMM function; this primitive is what PyTorch's bf16 `mm`
// runs). Built and run by benchmarks/compare only, never by the project's CMake.
//
//   gemm_openblas REPS MIN_SECONDS M,N,K,TA,TB [...]
// Prints one JSON object per shape and line: {"shape": "M,N,K,TA,TB", "seconds": [...]}
// with the mean time of one call in each of REPS repetitions (each repetition repeats
// the call for at least MIN_SECONDS, like Google Benchmark). Threads come from the
// environment (OPENBLAS_NUM_THREADS / OMP_NUM_THREADS), set by the caller. The bf16
// variant adds "isa": the implementation oneDNN chose (e.g. "brg:avx512_core_bf16"); its
// operands are converted to bf16 once, in the untimed warm-up call (nnshade's timing
// includes its conversion).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#if defined(YARDSTICK_OPENBLAS)
#include <cblas.h>
static void sgemm(bool ta, bool tb, int M, int N, int K, const float* A, int lda, const float* B, int ldb, float* C,
                  int ldc) {
  cblas_sgemm(CblasRowMajor, ta ? CblasTrans : CblasNoTrans, tb ? CblasTrans : CblasNoTrans, M, N, K, 1.0f, A, lda, B,
              ldb, 0.0f, C, ldc);
}
#elif defined(YARDSTICK_ONEDNN)
#include <dnnl.h>
static void sgemm(bool ta, bool tb, int M, int N, int K, const float* A, int lda, const float* B, int ldb, float* C,
                  int ldc) {
  // dnnl_sgemm is row-major, like ours.
  if (dnnl_sgemm(ta ? 'T' : 'N', tb ? 'T' : 'N', M, N, K, 1.0f, A, lda, B, ldb, 0.0f, C, ldc) != dnnl_success) {
    std::fprintf(stderr, "gemm_onednn: dnnl_sgemm failed\n");
    std::exit(1);
  }
}
#elif defined(YARDSTICK_ONEDNN_BF16)
#include <dnnl.hpp>
#include <map>
#include <memory>
#include <tuple>
static std::string g_isa;
static void sgemm(bool ta, bool tb, int M, int N, int K, const float* A, int lda, const float* B, int ldb, float* C,
                  int ldc) {
  using namespace dnnl;
  using dt = memory::data_type;
  static engine eng(engine::kind::cpu, 0);
  static stream st(eng);
  struct Prepared {
    memory a, b;
    matmul mm;
  };
  // One primitive and one bf16 copy of the operands per call site (shape and pointers).
  static std::map<std::tuple<const float*, const float*, float*>, std::unique_ptr<Prepared> > cache;
  auto& p = cache[{A, B, C}];
  if (!p) {
    // A transposed operand is the same logical matrix stored column-major (tag ba).
    const auto tag = [](bool t) { return t ? memory::format_tag::ba : memory::format_tag::ab; };
    memory af({{M, K}, dt::f32, tag(ta)}, eng, const_cast<float*>(A));
    memory bf({{K, N}, dt::f32, tag(tb)}, eng, const_cast<float*>(B));
    const memory::desc a_md({M, K}, dt::bf16, tag(ta)), b_md({K, N}, dt::bf16, tag(tb));
    const memory::desc c_md({M, N}, dt::f32, memory::format_tag::ab);
    p = std::make_unique<Prepared>();
    p->a = memory(a_md, eng);
    p->b = memory(b_md, eng);
    reorder(af, p->a).execute(st, af, p->a);
    reorder(bf, p->b).execute(st, bf, p->b);
    const matmul::primitive_desc pd(matmul::desc(a_md, b_md, c_md), eng);
    p->mm = matmul(pd);
    g_isa = pd.impl_info_str();
  }
  memory c({{M, N}, dt::f32, memory::format_tag::ab}, eng, C);
  p->mm.execute(st, {{DNNL_ARG_SRC, p->a}, {DNNL_ARG_WEIGHTS, p->b}, {DNNL_ARG_DST, c}});
  st.wait();
}
#else
#error "define YARDSTICK_OPENBLAS, YARDSTICK_ONEDNN or YARDSTICK_ONEDNN_BF16"
#endif

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s REPS MIN_SECONDS M,N,K,TA,TB [...]\n", argv[0]);
    return 2;
  }
  const int reps = std::atoi(argv[1]);
  const double min_seconds = std::atof(argv[2]);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  for (int a = 3; a < argc; ++a) {
    int M, N, K, ta, tb;
    if (std::sscanf(argv[a], "%d,%d,%d,%d,%d", &M, &N, &K, &ta, &tb) != 5) {
      std::fprintf(stderr, "%s: bad shape '%s', expected M,N,K,TA,TB\n", argv[0], argv[a]);
      return 2;
    }
    std::vector<float> A(size_t(M) * K), B(size_t(K) * N), C(size_t(M) * N);
    for (auto& x : A) x = uni(rng);
    for (auto& x : B) x = uni(rng);
    const int lda = ta ? M : K, ldb = tb ? K : N;
    auto call = [&] { sgemm(ta, tb, M, N, K, A.data(), lda, B.data(), ldb, C.data(), N); };
    call();  // warm-up: thread start, packing buffers
    std::string times;
    for (int r = 0; r < reps; ++r) {
      int64_t calls = 0;
      auto t0 = std::chrono::steady_clock::now();
      double elapsed = 0;
      do {
        call();
        ++calls;
        elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      } while (elapsed < min_seconds);
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s%.9g", r ? ", " : "", elapsed / double(calls));
      times += buf;
    }
    std::string extra;
#if defined(YARDSTICK_ONEDNN_BF16)
    extra = ", \"isa\": \"" + g_isa + "\"";
#endif
    std::printf("{\"shape\": \"%d,%d,%d,%d,%d\", \"seconds\": [%s]%s}\n", M, N, K, ta, tb, times.c_str(),
                extra.c_str());
    std::fflush(stdout);
  }
  return 0;
}
