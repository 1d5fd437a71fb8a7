#pragma once
// Camera placement: random cameras inside a scene's CameraRegion, kept only if a
// low-resolution probe of the view shows enough geometry (not mostly sky), not mostly
// one flat wall, and no wall pressed against the lens. Camera paths: smooth
// fly-throughs for temporal-stability measurements.
#include <vector>

#include "core/rng.h"
#include "render/camera.h"
#include "render/ray_tracer.h"

namespace nns::render {

struct PlacementRules {
  float max_sky_fraction = 0.3f;     // of probe pixels
  float max_plane_fraction = 0.55f;  // of hit pixels on one plane (within 2 deg, 3 cm)
  float min_median_depth = 0.8f;     // metres; less is a camera facing a close wall
  float min_clearance = 0.25f;       // no geometry closer than this to the eye
  int max_tries = 400;
  int candidates = 8;  // acceptable views compared; the least planar one wins
};

struct ProbeResult {
  float sky_fraction = 1, plane_fraction = 1, median_depth = 0, nearest = 0;
};

// Looks at the view through a probe of ~24x14 rays.
ProbeResult probe_view(const RayTracer& rt, const Camera& cam);
bool acceptable(const ProbeResult& p, const PlacementRules& rules);

// A camera of the given image size and fov, placed by the rules: of the first
// `candidates` acceptable views the one with the smallest largest plane (the most
// varied geometry); after max_tries the best candidate seen (fewest rule
// violations, then least sky) is returned.
Camera place_camera(const RayTracer& rt, int width, int height, float fov_y_deg, Rng& rng,
                    const PlacementRules& rules = {});

// `frames` cameras along a smooth path starting at an acceptable placement: the eye
// drifts on a gentle curve (~4 cm per frame) while yaw and pitch turn slowly; the path
// never passes through geometry. Falls back to a slow pan in place if no free path is
// found.
std::vector<Camera> camera_path(const RayTracer& rt, int width, int height, float fov_y_deg, int frames, Rng& rng,
                                const PlacementRules& rules = {});

}  // namespace nns::render
