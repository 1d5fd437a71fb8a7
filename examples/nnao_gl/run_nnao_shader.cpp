// run-nnao-shader: export-nnao's GLSL passes drawn by OpenGL on one G-buffer view, as
// an engine draws them (nnao_gl.h binds the textures and uniforms; headless_gl.h gives
// a context without a display: Mesa's llvmpipe where there is no GPU).
//   export-nnao --model nnao.blob --out shaders
//   run-nnao-shader --shaders shaders --in VIEW.exr --out AO.exr [--samples 64] [--frame 0] [--reference CPU.exr]
// The result is nnao-infer's image for the same view (--samples N for a grid model),
// within float rounding: tests/gl/test_nnao_glsl.cpp measures the difference.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "apps/args.h"
#include "data/exr_io.h"
#include "examples/nnao_gl/headless_gl.h"
#include "examples/nnao_gl/nnao_gl.h"

using namespace nns;

int main(int argc, char** argv) {
  return apps::run_main("run-nnao-shader", [&]() -> int {
    apps::Args args(argc, argv, "run-nnao-shader",
                    "Run export-nnao's GLSL passes on a G-buffer view (headless OpenGL).");
    std::string shaders = args.get_string("--shaders", "", "export-nnao's output folder");
    std::string in = args.get_string("--in", "", "input view (EXR with Z, N.X, N.Y, N.Z, fovY, aoRadius)");
    std::string out = args.get_string("--out", "", "output EXR (channel AO)");
    int samples = args.get_int("--samples", 64, "grid models: filter samples per pixel (uSamples)", 1, 1 << 20);
    int frame = args.get_int("--frame", 0, "grid models: frame index, the jitter pattern's seed (uFrame)", 0, INT_MAX);
    double radius = args.get_double("--radius", 0, "AO radius (0 = the view's aoRadius)", 0, HUGE_VAL);
    const std::string reference = args.get_string("--reference", "",
                                                  "an AO EXR of the same view (nnao-infer's): print the largest "
                                                  "difference and the pixels that differ by more than 1e-4");
    args.done();
    if (shaders.empty() || in.empty() || out.empty()) {
      std::fprintf(stderr, "run-nnao-shader: error: --shaders, --in and --out are required\n");
      return 2;
    }
    const data::View v = data::read_view(in);
    const screen_space::GBuffer g = screen_space::gbuffer_from_view(v, float(radius));
    gl::HeadlessGl context;
    gl::NnaoGlPasses passes(shaders);
    passes.set_gbuffer(g);
    const auto t0 = std::chrono::steady_clock::now();
    data::View o;
    o.width = v.width, o.height = v.height, o.fov_y_deg = v.fov_y_deg, o.ao_radius = g.radius, o.scene = v.scene;
    o.channels["Z"] = v.channel("Z");
    o.add_channel("AO") = passes.run({samples, uint32_t(frame)});
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    data::write_view(out, o);
    std::printf("%s: %dx%d on %s, %.1f ms (every pass and the read-back)\n", out.c_str(), v.width, v.height,
                context.renderer().c_str(), ms);
    if (!reference.empty()) {
      const data::View r = data::read_view(reference);
      if (r.width != v.width || r.height != v.height)
        throw std::runtime_error(reference + ": " + std::to_string(r.width) + "x" + std::to_string(r.height) +
                                 ", not the view's size");
      const auto& a = o.channel("AO");
      const auto& b = r.channel("AO");
      double worst = 0;
      size_t over = 0;
      for (size_t i = 0; i < a.size(); ++i) {
        const double d = std::abs(double(a[i]) - b[i]);
        worst = std::max(worst, std::isnan(d) ? INFINITY : d);
        over += !(d <= 1e-4);
      }
      std::printf("against %s: max |GPU - CPU| %.3g, %zu of %zu pixels differ by more than 1e-4\n", reference.c_str(),
                  worst, over, a.size());
    }
    return 0;
  });
}
