// export-nnao: a trained nnao.blob -> the engine's two passes as GLSL fragment shaders
// (nnao.frag with the network embedded, nnao_blur.frag) and, for a grid model, the
// filter atlas texture the shader reads plus the four filter images (the paper's
// Figure 2) (runs/ao/nnao_export.h; docs/nnao.md, "The shader in an engine").
#include <cstdio>

#include "apps/args.h"
#include "core/folder_lock.h"
#include "runs/ao/nnao_export.h"

using namespace nns;

int main(int argc, char** argv) {
  return cli::run_main("export-nnao", [&]() -> int {
    cli::Args args(argc, argv, "export-nnao", "Export NNAO as GLSL passes (and a grid model's filter texture) for engines.");
    std::string model = args.get_string("--model", "", "nnao.blob from train-nnao");
    std::string out = args.get_path("--out", "nnao-export", "output folder");
    int samples = args.get_int("--samples", 64, "grid models: the shader's default filter samples per pixel (uSamples)", 1, INT_MAX);
    args.done();
    if (model.empty()) {
      std::fprintf(stderr, "export-nnao: error: --model is required\n");
      return 2;
    }
    auto m = nnao::NnaoWeights::load(model);
    FolderLock lock = prepare_output_folder(out, "export-nnao");
    std::string files;
    for (const std::string& f : nnao::write_export(m, out, samples)) files += (files.empty() ? "" : ", ") + f;
    std::printf("wrote %s into %s (%s)\n", files.c_str(), out.c_str(),
                m.input.is_horizon() ? (std::to_string(m.input.samples()) + " depth samples per pixel, fixed by the model").c_str()
                                     : ("default " + std::to_string(samples) + " filter samples per pixel").c_str());
    return 0;
  });
}
