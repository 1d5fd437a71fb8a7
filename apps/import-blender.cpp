// import-blender: converts Blender multilayer EXR renders into the dataset format
// (docs/dataset-format.md); the recipe is docs/blender.md, the conversion data/blender_import.h.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "apps/args.h"
#include "data/blender_import.h"
#include "data/exr_io.h"

namespace fs = std::filesystem;
using nns::data::View;
using namespace nns::data::blender;

int main(int argc, char** argv) {
  nns::cli::Args args(argc, argv, "import-blender",
                      "Convert Blender multilayer EXR renders (ViewLayer.Depth.Z, ViewLayer.Normal.X, "
                      "DiffCol, DiffDir, DiffInd, Emit, AO) into the nnshade dataset format.");
  std::string out = args.get_string("--out", "", "output .exr (one input) or folder (required)");
  double fov = args.get_double("--fov-y", 0, "vertical field of view in degrees (required; docs/blender.md)", 0, 179);
  double ao_radius = args.get_double("--ao-radius", 0, "Blender's AO distance (required when an AO pass exists)", 0, HUGE_VAL);
  std::string scene = args.get_string("--scene", "", "scene name for splits (default: the file name)");
  std::string w2c = args.get_string("--world-to-camera", "",
                                    "16 numbers, row by row: camera.matrix_world.inverted() (default: file attribute)");
  std::string layer = args.get_string("--layer", "", "view layer to import (default: the only one)");
  bool keep_env = args.get_flag("--keep-env", "import Blender's Env pass (visible background) as env");
  bool half = args.get_flag("--half", "store channels other than Z as HALF");
  double sky = args.get_double("--sky-depth", 1e9, "depth at or above this is sky", 1e-6, HUGE_VAL);
  if (!(fov > 0 && fov < 180)) args.error("--fov-y: required, degrees in (0, 180)");
  if (out.empty()) args.error("--out: required");
  if (args.positional().empty()) args.error("expected at least one Blender EXR");
  args.done("BLENDER.exr ...");

  return nns::cli::run_main("import-blender", [&] {
    ImportSettings s;
    s.fov_y = float(fov);
    if (ao_radius > 0) s.ao_radius = float(ao_radius);
    s.scene = scene;
    s.layer = layer;
    if (!w2c.empty()) s.world_to_camera = parse_matrix(w2c);
    s.keep_env = keep_env;
    s.half = half;
    s.sky_depth = float(sky);
    const auto& inputs = args.positional();
    const bool to_file = inputs.size() == 1 && fs::path(out).extension() == ".exr";
    if (!to_file) fs::create_directories(out);
    for (auto& in : inputs) {
      nns::data::ReadOptions ro;
      ro.require_attributes = false;
      View v = nns::data::read_view(in, ro);
      View converted = convert(v, s);
      std::string dst = to_file ? out : (fs::path(out) / fs::path(in).filename()).string();
      nns::data::WriteOptions wo;
      wo.half = s.half;
      nns::data::write_view(dst, converted, wo);
      std::printf("%s -> %s (%zu channels)\n", in.c_str(), dst.c_str(), converted.channels.size());
    }
    return 0;
  });
}
