// SGEMM yardstick: times the same row-major shapes as build/benchmarks/bench_gemm in
// OpenBLAS (-DYARDSTICK_OPENBLAS, cblas_sgemm) or oneDNN (-DYARDSTICK_ONEDNN,
// dnnl_sgemm). Built and run by benchmarks/compare only, never by the project's CMake.
//
//   gemm_openblas REPS MIN_SECONDS M,N,K,TA,TB [...]
// Prints one JSON object per shape and line: {"shape": "M,N,K,TA,TB", "seconds": [...]}
// with the mean time of one call in each of REPS repetitions (each repetition repeats
// the call for at least MIN_SECONDS, like Google Benchmark). Threads come from the
// environment (OPENBLAS_NUM_THREADS / OMP_NUM_THREADS), set by the caller.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#if defined(YARDSTICK_OPENBLAS)
#include <cblas.h>
static void sgemm(bool ta, bool tb, int M, int N, int K, const float* A, int lda, const float* B,
                  int ldb, float* C, int ldc) {
  cblas_sgemm(CblasRowMajor, ta ? CblasTrans : CblasNoTrans, tb ? CblasTrans : CblasNoTrans, M, N,
              K, 1.0f, A, lda, B, ldb, 0.0f, C, ldc);
}
#elif defined(YARDSTICK_ONEDNN)
#include <dnnl.h>
static void sgemm(bool ta, bool tb, int M, int N, int K, const float* A, int lda, const float* B,
                  int ldb, float* C, int ldc) {
  // dnnl_sgemm is row-major, like ours.
  if (dnnl_sgemm(ta ? 'T' : 'N', tb ? 'T' : 'N', M, N, K, 1.0f, A, lda, B, ldb, 0.0f, C, ldc) !=
      dnnl_success) {
    std::fprintf(stderr, "gemm_onednn: dnnl_sgemm failed\n");
    std::exit(1);
  }
}
#else
#error "define YARDSTICK_OPENBLAS or YARDSTICK_ONEDNN"
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
    std::printf("{\"shape\": \"%d,%d,%d,%d,%d\", \"seconds\": [%s]}\n", M, N, K, ta, tb,
                times.c_str());
    std::fflush(stdout);
  }
  return 0;
}
