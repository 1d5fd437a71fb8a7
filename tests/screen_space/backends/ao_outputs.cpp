// Writes the output of every screen-space AO method (each classical method at each
// sample count eval-ao runs, NNAO's horizon and grid models at full, half and quarter
// resolution, shader-style NNAO) on synthetic frames to one raw file. Built twice, with
// the build's simd16 backend and with the generic one (NNSHADE_SIMD16_GENERIC=1); the
// ctest screen_space.backends_agree compares the two files: what
// tests/screen_space/test_simd16.cpp cannot see, the expressions written with the
// operations, must come out the same too.
//
// Not byte for byte: GCC fuses a * b + c into an FMA (-ffp-contract=fast, its default)
// also across an inlined call, and it inlines by code size, which differs between the
// backends. In this program the generic build keeps simd::acos (gtao.h) and
// CentreBlock::sample (nnao_inference.h) out of line, so a product that the inlined
// copy shares with a non-sum (and so does not fuse) is fused in the other: GTAO and
// shader-style NNAO differ by <= 4 ulp (2012 of the 255,664 floats on the AMD Zen 2
// where this was written; with acos forced inline, 20), every other method is bitwise
// equal. A wrong operation differs by far more than kMaxUlps.
//   ao_outputs OUT.raw            write
//   ao_outputs --compare A B      0 when every float is within kMaxUlps (NaN only with NaN)
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <tuple>
#include <string>
#include <vector>

#include "classical_ao/methods.h"
#include "classical_ao/params.h"
#include "core/blob.h"
#include "fixtures/random_nnao_blob.h"
#include "fixtures/synthetic_gbuffer.h"
#include "models/nnao/nnao_inference.h"

using namespace nns;

namespace {

constexpr int64_t kMaxUlps = 8;

// Floats as integers in the order of their values (-0 and +0 the same), so that a difference
// of integers counts the floats between.
int64_t ordered(float x) {
  int32_t i;
  std::memcpy(&i, &x, sizeof i);
  return i < 0 ? int64_t(INT32_MIN) - int64_t(i) : int64_t(i);
}

std::vector<float> read_floats(const char* path) {
  std::FILE* f = std::fopen(path, "rb");
  if (!f) throw std::runtime_error(std::string("cannot read ") + path);
  std::vector<float> v;
  float x;
  while (std::fread(&x, sizeof x, 1, f) == 1) v.push_back(x);
  std::fclose(f);
  return v;
}

int compare(const char* a_path, const char* b_path) {
  const std::vector<float> a = read_floats(a_path), b = read_floats(b_path);
  if (a.size() != b.size()) {
    std::fprintf(stderr, "ao_outputs: %s has %zu floats, %s %zu\n", a_path, a.size(), b_path, b.size());
    return 1;
  }
  int64_t differ = 0, worst = 0;
  size_t worst_at = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) != std::isnan(b[i])) {
      std::fprintf(stderr, "ao_outputs: float %zu: %g against %g\n", i, double(a[i]), double(b[i]));
      return 1;
    }
    if (std::isnan(a[i])) continue;
    const int64_t d = std::llabs(ordered(a[i]) - ordered(b[i]));
    differ += d != 0;
    if (d > worst) worst = d, worst_at = i;
  }
  std::printf("%lld of %zu floats differ, by at most %lld ulp (float %zu: %.9g against %.9g)\n", (long long)differ,
              a.size(), (long long)worst, worst_at, double(a[worst_at]), double(b[worst_at]));
  return worst <= kMaxUlps ? 0 : 1;
}

void write_outputs(std::FILE* f) {
  std::vector<nnao::NnaoWeights> models;
  for (int downsample : {1, 2, 4}) {
    Blob horizon = fixtures::random_nnao_blob(0, 16, 7, false, {8, 8, 4});
    horizon.set_config("blur_passes", 2);
    horizon.set_config("downsample", downsample);
    models.push_back(nnao::NnaoWeights::from_blob(horizon));
    Blob grid = fixtures::random_nnao_blob(7, 4, 11);
    grid.set_config("blur_passes", 1);
    grid.set_config("downsample", downsample);
    models.push_back(nnao::NnaoWeights::from_blob(grid));
  }
  const classical_ao::ClassicalParams params;
  // Widths that leave a row's last block part empty (the masked loads and stores).
  for (auto [w, h, variant] : {std::tuple{67, 45, 0}, std::tuple{96, 40, 1}, std::tuple{53, 37, 2}}) {
    const data::View view = fixtures::synthetic_view(w, h, variant, 1);
    const screen_space::GBuffer g = screen_space::gbuffer_from_view(view);
    std::vector<float> out(size_t(g.pixels()));
    auto put = [&] { std::fwrite(out.data(), sizeof(float), out.size(), f); };
    for (auto& c : classical_ao::classical_methods())
      for (int n : c.sample_counts) classical_ao::run_classical(c.name, params, g, n, out.data(), false), put();
    for (const auto& m : models) {
      nnao::infer_exact(m, g, out.data()), put();
      if (!m.input.is_horizon()) nnao::infer_shader_style(m, g, 16, out.data()), put();
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--compare") {
    try {
      return compare(argv[2], argv[3]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ao_outputs: %s\n", e.what());
      return 1;
    }
  }
  if (argc != 2) {
    std::fprintf(stderr, "usage: ao_outputs OUT.raw | ao_outputs --compare A.raw B.raw\n");
    return 2;
  }
  std::FILE* f = std::fopen(argv[1], "wb");
  if (!f) {
    std::fprintf(stderr, "ao_outputs: cannot write %s\n", argv[1]);
    return 1;
  }
  std::printf("simd16 backend: %s\n", screen_space::simd::kBackend);
  try {
    write_outputs(f);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ao_outputs: %s\n", e.what());
    return 1;
  }
  return std::fclose(f) == 0 ? 0 : 1;
}
