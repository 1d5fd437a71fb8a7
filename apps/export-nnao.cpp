// export-nnao: a trained nnao.blob -> the four filter images (EXR + PNG, the paper's
// Figure 2), the filter atlas texture and a GLSL fragment shader with the network's
// constants embedded (runs/ao/nnao_export.h).
#include <cstdio>
#include <filesystem>

#include "core/atomic_file.h"
#include "apps/args.h"
#include "report/chart.h"
#include "runs/ao/nnao_export.h"

using namespace nns;

int main(int argc, char** argv) {
  return cli::run_main("export-nnao", [&]() -> int {
    cli::Args args(argc, argv, "export-nnao", "Export NNAO filters and a GLSL shader for engines.");
    std::string model = args.get_string("--model", "", "nnao.blob from train-nnao");
    std::string out = args.get_string("--out", "nnao-export", "output folder");
    int samples = args.get_int("--samples", 64, "filter samples per pixel in the shader", 1, INT_MAX);
    args.done();
    if (model.empty()) {
      std::fprintf(stderr, "export-nnao: error: --model is required\n");
      return 2;
    }
    auto m = nnao::NnaoWeights::load(model);
    nnao::check_sample_count(samples, m.input);
    nnao::write_filter_images(m, out);
    const std::string frag = (std::filesystem::path(out) / "nnao.frag").string();
    write_file_atomic(frag, nnao::glsl_shader(m, samples));
    std::printf("wrote %d filters (filter<k>.exr/.png), nnao_filters.exr and %s\n", m.hidden, frag.c_str());
    return 0;
  });
}
