// nnao-infer: NNAO on one G-buffer view.
//   nnao-infer --model nnao.blob --in VIEW.exr --out AO.exr [--samples N] [--png AO.png]
//   nnao-infer --model nnao.blob --channel depth=d.exr:Z --channel normal=n.png --fov-y 60 --out AO.exr
// --samples 0 runs the exact network (all w*w grid samples); N > 0 the shader-style
// approximation with N filter samples and the bilateral blur.
#include <chrono>
#include <cstdio>
#include <thread>

#include "apps/args.h"
#include "core/atomic_file.h"
#include "apps/image_input_flags.h"
#include "core/thread_pool.h"
#include "data/exr_io.h"
#include "report/image_write.h"
#include "models/nnao/nnao_inference.h"

using namespace nns;

int main(int argc, char** argv) {
  return apps::run_main("nnao-infer", [&]() -> int {
    apps::Args args(argc, argv, "nnao-infer", "Run NNAO on one G-buffer view.");
    std::string model = args.get_string("--model", "", "nnao.blob from train-nnao");
    std::string in = args.get_string("--in", "", "input view (EXR with Z, N.X, N.Y, N.Z; or --channel)");
    apps::ImageInputFlags images = apps::image_input_flags(args, "nnao-infer", {"depth", "normal"});
    std::string out = args.get_path("--out", "", "output EXR (channel AO)");
    std::string png = args.get_string("--png", "", "also write a PNG preview");
    int samples =
        args.get_int("--samples", 0, "0 = exact; else shader-style filter samples (64, 128, 256, ...)", 0, INT_MAX);
    double radius =
        args.get_double("--radius", 0, "AO radius (0 = the view's aoRadius, else the model's)", 0, HUGE_VAL);
    int threads = args.get_int("--threads", 2, "worker threads", 1, 256);
    if (!in.empty() && !images.channels.empty()) args.error("--in and --channel are alternatives; give one");
    args.done();
    if (model.empty() || (in.empty() && images.channels.empty()) || out.empty()) {
      std::fprintf(stderr, "nnao-infer: error: --model, --in (or --channel) and --out are required\n");
      return 2;
    }
    set_num_threads(threads);
    auto m = nnao::NnaoWeights::load(model);
    if (samples > 0) nnao::check_sample_count(samples, m.input);
    data::View v = images.channels.empty() ? data::read_view(in) : data::view_from_images(images.channels, images.view);
    float r = float(radius);
    if (r <= 0 && !v.ao_radius && m.radius > 0) r = m.radius;
    screen_space::GBuffer g = screen_space::gbuffer_from_view(v, r);
    data::View o;
    o.width = v.width;
    o.height = v.height;
    o.fov_y_deg = v.fov_y_deg;
    o.ao_radius = g.radius;
    o.scene = v.scene;
    o.world_to_camera = v.world_to_camera;
    o.channels["Z"] = v.channel("Z");
    auto& ao_plane = o.add_channel("AO");
    auto t0 = std::chrono::steady_clock::now();
    if (samples == 0) nnao::infer_exact(m, g, ao_plane.data());
    else nnao::infer_shader_style(m, g, samples, ao_plane.data());
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // What a killed earlier run left beside the targets (core/atomic_file.h's names).
    remove_stale_temporaries_of(out);
    if (!png.empty()) remove_stale_temporaries_of(png);
    data::write_view(out, o);
    if (!png.empty()) report::write_png_gray(png, ao_plane.data(), o.width, o.height);
    std::printf("%s: %dx%d, %s, %.2f ms\n", out.c_str(), o.width, o.height,
                samples ? ("shader-style " + std::to_string(samples) + " samples").c_str() : "exact", ms);
    return 0;
  });
}
