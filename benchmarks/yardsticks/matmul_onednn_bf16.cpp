// bf16 GEMM yardstick: oneDNN's matmul primitive with bf16 source and weights and an
// fp32 destination (Debian's oneDNN 2.6 has no public bf16 GEMM function; this primitive
// is what PyTorch's bf16 `mm` runs), on the row-major shapes of bench_gemm's BM_GemmBf16.
// Built and run by benchmarks/compare only, never by the project's CMake.
//
//   matmul_onednn_bf16 REPS MIN_SECONDS M,N,K,TA,TB [...]
// Prints one JSON object per shape and line, as gemm_blas.cpp, plus "isa": the
// implementation oneDNN chose (e.g. "brg:avx512_core_bf16"). The operands are bf16 in
// memory already (converted once, untimed); nnshade's timing includes its conversion.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <dnnl.hpp>

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s REPS MIN_SECONDS M,N,K,TA,TB [...]\n", argv[0]);
    return 2;
  }
  using namespace dnnl;
  using dt = memory::data_type;
  const int reps = std::atoi(argv[1]);
  const double min_seconds = std::atof(argv[2]);
  engine eng(engine::kind::cpu, 0);
  stream st(eng);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  for (int a = 3; a < argc; ++a) {
    int M, N, K, ta, tb;
    if (std::sscanf(argv[a], "%d,%d,%d,%d,%d", &M, &N, &K, &ta, &tb) != 5) {
      std::fprintf(stderr, "%s: bad shape '%s', expected M,N,K,TA,TB\n", argv[0], argv[a]);
      return 2;
    }
    // A transposed operand is the same logical matrix stored column-major (tag ba).
    const memory::desc a_f32({M, K}, dt::f32, ta ? memory::format_tag::ba : memory::format_tag::ab);
    const memory::desc b_f32({K, N}, dt::f32, tb ? memory::format_tag::ba : memory::format_tag::ab);
    const memory::desc a_md({M, K}, dt::bf16, ta ? memory::format_tag::ba : memory::format_tag::ab);
    const memory::desc b_md({K, N}, dt::bf16, tb ? memory::format_tag::ba : memory::format_tag::ab);
    const memory::desc c_md({M, N}, dt::f32, memory::format_tag::ab);
    memory af(a_f32, eng), bf(b_f32, eng), am(a_md, eng), bm(b_md, eng), cm(c_md, eng);
    for (size_t i = 0; i < size_t(M) * K; ++i) static_cast<float*>(af.get_data_handle())[i] = uni(rng);
    for (size_t i = 0; i < size_t(K) * N; ++i) static_cast<float*>(bf.get_data_handle())[i] = uni(rng);
    reorder(af, am).execute(st, af, am);
    reorder(bf, bm).execute(st, bf, bm);
    const matmul::primitive_desc pd(matmul::desc(a_md, b_md, c_md), eng);
    const matmul mm(pd);
    auto call = [&] {
      mm.execute(st, {{DNNL_ARG_SRC, am}, {DNNL_ARG_WEIGHTS, bm}, {DNNL_ARG_DST, cm}});
      st.wait();
    };
    call();  // warm-up
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
    std::printf("{\"shape\": \"%d,%d,%d,%d,%d\", \"seconds\": [%s], \"isa\": \"%s\"}\n", M, N, K, ta,
                tb, times.c_str(), pd.impl_info_str());
    std::fflush(stdout);
  }
  return 0;
}
