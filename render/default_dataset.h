#pragma once
// The built-in default datasets: what the trainers use when run without --data.
// Rendered once (deterministic, seeded, with a progress bar) into a cache folder and
// reused after:
//
//   $NNSHADE_CACHE, else $XDG_CACHE_HOME/nnshade, else ~/.cache/nnshade
//     default-<preset>-v<version>/         train/ + test/ + COMPLETE (a manifest)
//
// The render goes to "<folder>.partial-<pid>" and is renamed when complete, so an
// interrupted render never leaves a folder that looks finished.
#include <string>

#include "render/dataset_writer.h"

namespace nns::render {

// Bumped whenever the renderer, the scenes or the sizes below change the pixels; the
// cache folder is default-<preset>-v<version>. nnao is at 4 (nnao-v2 families, holdout/,
// camera paths, three test scenes per family); surround is at 6 (surround-v5: all 24
// families, textured materials, lights varied, holdout/, 2,400 frames, 128x128 faces;
// train/ at 64 paths, test/ and holdout/ at 128: version 5's test/ and holdout/ bytes;
// without the AO channel, which nothing of GI reads: a version-6 folder that has it holds
// the same pixels in every other channel, so the version stays 6);
// gi is at 3 (the renderer's faster estimator changed its noise).
inline int default_dataset_version(const std::string& preset) {
  return preset == "nnao" ? 4 : preset == "surround" ? 6 : 3;
}

// The job that renders the default dataset of `preset` ("nnao", "surround", "gi"):
// sizes, views and sample counts live here, in one place (docs/renderer.md explains
// the choice).
DatasetJob default_dataset_job(const std::string& preset);

// The cache root (see above); throws if no variable gives one.
std::string default_cache_root();

// The folder of the default dataset for `preset`, rendering it first if needed.
std::string ensure_default_dataset(const std::string& preset, int threads);

// The mechanism behind it, for any job: returns root/name if it holds a COMPLETE
// marker, else renders `job` to root/name.partial-<pid> and renames it into place.
std::string ensure_rendered_dataset(DatasetJob job, const std::string& root, const std::string& name, int threads);

}  // namespace nns::render
