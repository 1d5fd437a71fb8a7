// import-blender: converts Blender multilayer EXR renders into the dataset format
// (docs/dataset-format.md); the recipe is docs/blender.md, the conversion data/blender_import.h.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "apps/args.h"
#include "core/folder_lock.h"
#include "data/blender_import.h"
#include "data/exr_io.h"

namespace fs = std::filesystem;
using nns::data::View;
using namespace nns::data::blender;

namespace {

struct Job {
  std::string in, out;
};

// Every input file and where it goes. A folder input is converted whole (every .exr
// under it, sub-folders kept: tools/blender_capture.py's OUT/<camera>-surround/<face>.exr
// becomes a surround frame); a file input keeps its name. Checked before anything is written.
std::vector<Job> plan(const std::vector<std::string>& inputs, const std::string& out) {
  const bool to_file = inputs.size() == 1 && fs::path(out).extension() == ".exr" && !fs::is_directory(inputs[0]);
  std::vector<Job> jobs;
  for (auto& in : inputs) {
    if (to_file) {
      jobs.push_back({in, out});
    } else if (fs::is_directory(in)) {
      std::vector<fs::path> found;
      for (auto& e : fs::recursive_directory_iterator(in))
        if (e.is_regular_file() && e.path().extension() == ".exr" &&
            e.path().string().find(".partial-") == std::string::npos)
          found.push_back(e.path());
      if (found.empty()) throw std::runtime_error(in + ": folder holds no .exr file");
      std::sort(found.begin(), found.end());
      for (auto& f : found) jobs.push_back({f.string(), (fs::path(out) / fs::relative(f, in)).string()});
    } else {
      jobs.push_back({in, (fs::path(out) / fs::path(in).filename()).string()});
    }
  }
  std::map<std::string, std::string> seen;
  for (auto& j : jobs) {
    auto [it, fresh] = seen.emplace(fs::weakly_canonical(j.out).string(), j.in);
    if (!fresh) throw std::runtime_error(j.in + " and " + it->second + " would both be written to " + j.out);
  }
  return jobs;
}

}  // namespace

int main(int argc, char** argv) {
  nns::apps::Args args(argc, argv, "import-blender",
                       "Convert Blender multilayer EXR renders (ViewLayer.Depth.Z, ViewLayer.Normal.X, "
                       "DiffCol, DiffDir, DiffInd, Emit, AO) into the nnshade dataset format. Files rendered by "
                       "tools/blender_capture.py carry their camera in the header; a flag given here overrides it "
                       "(with a note). Inputs are files or folders (converted whole, sub-folders kept).");
  std::string out = args.get_path("--out", "", "output .exr (one input file) or folder (required)");
  double fov =
      args.get_double("--fov-y", 0, "vertical field of view in degrees (default: the file's capture note)", 0, 179);
  double ao_radius =
      args.get_double("--ao-radius", 0, "Blender's AO distance (default: the file's capture note)", 0, HUGE_VAL);
  std::string scene =
      args.get_string("--scene", "", "scene name for splits (default: capture note, else the file name)");
  std::string w2c = args.get_string("--world-to-camera", "",
                                    "16 numbers, row by row: camera.matrix_world.inverted() (default: capture note, "
                                    "else a worldToCamera attribute)");
  std::string layer = args.get_string("--layer", "", "view layer to import (default: the only one)");
  bool keep_env = args.get_flag("--keep-env", "import Blender's Env pass (visible background) as env");
  bool half = args.get_flag("--half", "store channels other than Z as HALF");
  double sky = args.get_double("--sky-depth", 1e9, "depth at or above this is sky", 1e-6, HUGE_VAL);
  if (out.empty()) args.error("--out: required");
  if (args.positional().empty()) args.error("expected at least one Blender EXR or folder");
  args.done("BLENDER.exr|FOLDER ...");

  return nns::apps::run_main("import-blender", [&] {
    ImportSettings flags;
    flags.fov_y = float(fov);
    if (ao_radius > 0) flags.ao_radius = float(ao_radius);
    flags.scene = scene;
    flags.layer = layer;
    if (!w2c.empty()) flags.world_to_camera = parse_matrix(w2c);
    flags.keep_env = keep_env;
    flags.half = half;
    flags.sky_depth = float(sky);
    // Every header and capture note is read before the first file is written, so a bad
    // note stops the import with nothing written.
    std::vector<Job> jobs = plan(args.positional(), out);
    std::vector<ImportSettings> settings;
    for (auto& job : jobs) {
      nns::data::ReadOptions ro;
      ro.require_attributes = false;
      ro.header_only = true;
      nns::data::ExrInfo info;
      nns::data::read_view(job.in, ro, &info);
      auto note = info.strings.find("Note");
      std::vector<std::string> overrides;
      settings.push_back(with_capture_note(
          flags, note == info.strings.end() ? std::nullopt : parse_capture_note(note->second, job.in), &overrides));
      for (auto& o : overrides) std::fprintf(stderr, "import-blender: %s: %s\n", job.in.c_str(), o.c_str());
      require_fov(settings.back(), job.in);
    }
    // A folder output is locked, as every folder a command writes (core/folder_lock.h):
    // two imports into one folder would otherwise mix their views unnoticed.
    nns::FolderLock lock;
    if (!(jobs.size() == 1 && jobs[0].out == out)) lock = nns::prepare_output_folder(out, "import-blender");
    std::vector<std::string> written;
    try {
      for (size_t i = 0; i < jobs.size(); ++i) {
        nns::data::ReadOptions ro;
        ro.require_attributes = false;
        View converted = convert(nns::data::read_view(jobs[i].in, ro), settings[i]);
        if (fs::path(jobs[i].out).has_parent_path()) fs::create_directories(fs::path(jobs[i].out).parent_path());
        nns::data::WriteOptions wo;
        wo.half = settings[i].half;
        nns::data::write_view(jobs[i].out, converted, wo);
        written.push_back(jobs[i].out);
        std::printf("%s -> %s (%zu channels)\n", jobs[i].in.c_str(), jobs[i].out.c_str(), converted.channels.size());
      }
    } catch (...) {
      // Half an import is no dataset: the files written so far go, and the folder with
      // them if this run made it (the lock removes a made folder left empty).
      for (const auto& f : written) {
        std::error_code ec;
        fs::remove(f, ec);
      }
      throw;
    }
    return 0;
  });
}
