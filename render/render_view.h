#pragma once
// render_view: one camera view of a scene -> a dataset View with every channel of the
// spec (docs/dataset-format.md, docs/renderer.md). Runs on the global thread pool;
// each pixel draws from its own Rng seeded by (seed, view id, pixel), so the image is
// identical for any number of threads.
#include <cstdint>

#include "render/camera.h"
#include "render/integrator.h"
#include "data/view.h"

namespace nns::render {

struct RenderStats {
  uint64_t rays = 0;
  double seconds = 0;
};

// `normal_frame` (optional) is the camera whose space the normals are written in;
// surround faces pass the front camera. Sky pixels get Z = inf, N = 0, AO = 1 and the
// sky's radiance as `emission` (so albedo*(...)+emission is the image everywhere).
data::View render_view(const RayTracer& rt, const Camera& cam, const RenderSettings& settings, uint64_t view_id,
                       const Camera* normal_frame = nullptr, RenderStats* stats = nullptr);

}  // namespace nns::render
