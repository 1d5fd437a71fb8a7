// gi-infer: a trained GI generator on one frame without ground truth.
//
//   gi-infer --model gan-out/G.blob --in frame7 --out frame7_gi.exr
//   gi-infer --model G.blob --channel depth=d.exr:Z --channel normal=n.png --channel albedo=a.png \
//            --channel direct=direct.hdr --fov-y 60 --out f_gi.exr
//   gi-infer --model G.blob --channel front.depth=f_d.exr:Z --channel front.normal=f_n.png ... \
//            --channel down.direct=d_direct.exr --out f_gi.exr      (surround: six faces, 90 degrees)
// --in is one G-buffer view (front-mode model) or a folder of six faces
// front/back/left/right/up/down.exr (surround model). Writes OUT.exr (light.*, indirect.*,
// shaded.*, Z) and OUT_shaded.png, OUT_indirect.png; on any error, nothing. See docs/gan.md.
#include <cstdio>

#include "apps/args.h"
#include "apps/image_input_flags.h"
#include "core/thread_pool.h"
#include "runs/gi/gi_infer.h"

using namespace nns;

int main(int argc, char** argv) {
  return apps::run_main("gi-infer", [&] {
    apps::Args a(argc, argv, "gi-infer",
                 "Predict indirect light and the lit image of one G-buffer frame with a trained GI generator.\n"
                 "--in: a view EXR (front-mode model) or a folder with front/back/left/right/up/down.exr\n"
                 "(surround model); needs Z, N.X/Y/Z, albedo.R/G/B, direct.R/G/B (emission, env optional),\n"
                 "no indirect.*. Or the frame as your own images, --channel (below): TARGET=FILE for a\n"
                 "front-mode model, FACE.TARGET=FILE on each of the six faces for a surround model.\n"
                 "Views larger than the model's face size are box-filtered down by an integer\n"
                 "factor for the network, and its indirect light is brought back up to their size by an\n"
                 "upsample guided by their depth and normals (--output-size). Writes OUT.exr (light.*, indirect.* = "
                 "light - direct - env, signed; shaded.* =\n"
                 "albedo * light + emission; Z), OUT_shaded.png and OUT_indirect.png; on error, nothing.");
    runs::InferOptions o;
    o.model = a.get_string("--model", "", "generator blob (G.blob) from train-gan");
    o.in = a.get_string("--in", "", "the frame: a view .exr or a folder of six faces (or --channel)");
    apps::ImageInputFlags images =
        apps::image_input_flags(a, "gi-infer", {"depth", "normal", "albedo", "direct"}, {"emission", "env"},
                                /*surround=*/true);
    o.channels = images.channels;
    o.images = images.view;
    o.out = a.get_path("--out", "", "output .exr (default: <input name>_gi.exr in the current folder)");
    std::string bn = a.get_choice("--test-bn", "batch", {"batch", "running"}, "BatchNorm statistics, as eval-gi");
    std::string drop = a.get_choice("--test-dropout", "off", {"on", "off"}, "dropout at test time, as eval-gi");
    o.mirror_average = a.get_flag("--mirror-average",
                                  "average the light with the light for the mirrored frame, mirrored back (twice "
                                  "the network's time; surround needs an even face size), as eval-gi");
    std::string out_size = a.get_choice("--output-size", "input", {"input", "model"},
                                        "output at the input's size (guided upsample) or at the model's face size");
    int threads = a.get_int("--threads", 2, "worker threads", 1, 256);
    if (o.model.empty()) a.error("--model is required");
    if (o.in.empty() && o.channels.empty()) a.error("--in (or --channel) is required");
    if (!o.in.empty() && !o.channels.empty()) a.error("--in and --channel are alternatives; give one");
    a.done();
    o.bn_batch_stats = bn == "batch";
    o.dropout_on = drop == "on";
    o.output_at_input_size = out_size == "input";
    set_num_threads(threads);
    runs::InferResult r = runs::infer_gi(o);
    for (auto& note : r.notes) std::printf("gi-infer: %s\n", note.c_str());
    std::printf("gi-infer: %s model, %s %dx%d, box filter %d for the network (%.1f ms)", r.mode.c_str(),
                r.front_file.c_str(), r.in_width, r.in_height, r.reduction, r.ms);
    if (r.upsampled) std::printf(", guided upsample back to %dx%d (%.1f ms)", r.width, r.height, r.upsample_ms);
    std::printf("; output %dx%d\n", r.width, r.height);
    std::printf(
        "gi-infer: predicted light below direct+env (negative indirect, kept signed in the EXR) on "
        "%lld of %lld geometry pixels, minimum %.4g\n",
        (long long)r.negative_indirect_pixels, (long long)r.geometry_pixels, double(r.min_indirect));
    std::printf("gi-infer: wrote %s, %s, %s\n", r.exr.c_str(), r.shaded_png.c_str(), r.indirect_png.c_str());
    return 0;
  });
}
