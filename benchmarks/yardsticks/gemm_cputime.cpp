// SGEMM, one thread, nnshade vs OpenBLAS vs oneDNN in one process, timed with the
// thread's CPU clock and the sides alternated call batch by call batch. For a loaded,
// shared machine, where wall-clock benchmarks measure the neighbours: CPU time counts
// only the cycles this thread ran (cache pollution by the neighbours still counts).
// Not built by CMake; benchmarks/compare's wall-clock table is the reference.
//
//   g++ -O3 -march=native -std=c++20 -I. benchmarks/yardsticks/gemm_cputime.cpp
//       -o /tmp/gemm_cputime -lopenblas -ldnnl -lpthread
//   env -u OPENBLAS_CORETYPE -u OPENBLAS_L2_SIZE OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
//       /tmp/gemm_cputime
#include <cblas.h>
#include <dnnl.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "core/kernels/gemm.h"

static double thread_seconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

int main() {
  nns::ThreadPool::global();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // thread_pool.h start-up race
  nns::set_num_threads(1);
  const int64_t shapes[][5] = {{256, 256, 256, 0, 0},    {512, 512, 512, 0, 0},   {1024, 1024, 1024, 0, 0},
                               {2048, 2048, 2048, 0, 0}, {64, 16384, 48, 0, 0},   {128, 4096, 1024, 0, 0},
                               {256, 1024, 2048, 0, 0},  {512, 256, 4096, 0, 0},  {512, 64, 8192, 0, 0},
                               {2048, 1024, 512, 1, 0},  {1024, 4096, 256, 1, 0}, {128, 1024, 4096, 0, 1},
                               {256, 2048, 1024, 0, 1}};
  std::printf("| sgemm M,N,K,ta,tb | nnshade | OpenBLAS | oneDNN | nnshade / best |\n");
  std::printf("|---|---:|---:|---:|---:|\n");
  for (const auto& s : shapes) {
    const int64_t M = s[0], N = s[1], K = s[2];
    const bool ta = s[3], tb = s[4];
    std::vector<float> A(size_t(M * K)), B(size_t(K * N)), C(size_t(M * N));
    for (size_t i = 0; i < A.size(); ++i) A[i] = float(i % 7) * 0.1f;
    for (size_t i = 0; i < B.size(); ++i) B[i] = float(i % 5) * 0.1f;
    const int lda = int(ta ? M : K), ldb = int(tb ? K : N);
    const double flops = 2.0 * double(M * N * K);
    const int calls = int(std::max<double>(1, 2e8 / flops));
    double best[3] = {1e30, 1e30, 1e30};
    for (int round = 0; round < 6; ++round)
      for (int side = 0; side < 3; ++side) {
        const double t0 = thread_seconds();
        for (int q = 0; q < calls; ++q) {
          if (side == 0) nns::gemm<float>(ta, tb, M, N, K, 1.0f, A.data(), lda, B.data(), ldb, 0.0f, C.data(), N);
          else if (side == 1)
            cblas_sgemm(CblasRowMajor, ta ? CblasTrans : CblasNoTrans, tb ? CblasTrans : CblasNoTrans, int(M), int(N),
                        int(K), 1.0f, A.data(), lda, B.data(), ldb, 0.0f, C.data(), int(N));
          else
            dnnl_sgemm(ta ? 'T' : 'N', tb ? 'T' : 'N', M, N, K, 1.0f, A.data(), lda, B.data(), ldb, 0.0f, C.data(), N);
        }
        best[side] = std::min(best[side], (thread_seconds() - t0) / calls);
      }
    std::printf("| sgemm %ld,%ld,%ld,%d,%d | %.1f | %.1f | %.1f | %.2fx |\n", long(M), long(N), long(K), int(ta),
                int(tb), flops / best[0] / 1e9, flops / best[1] / 1e9, flops / best[2] / 1e9,
                std::min(best[1], best[2]) / best[0]);
  }
  return 0;
}
