#pragma once
// The view the GL tests draw: a family scene through the ground-truth renderer, depth
// and normals as the datasets hold them (AO rays are not needed: one per pixel). Real
// geometry, unlike the synthetic boxes, whose axis-aligned faces put many samples on
// exact pixel edges.
#include "core/rng.h"
#include "render/placement.h"
#include "render/render_view.h"
#include "render/scenes/families.h"

namespace nns::testing {

inline const data::View& rendered_view() {
  static const data::View v = [] {
    render::Scene s = render::make_family_scene("room", 1, 3);
    render::RayTracer rt(s);
    Rng rng(5);
    render::Camera cam = render::place_camera(rt, 160, 90, 60, rng);
    render::RenderSettings rs;
    rs.lighting = false;
    rs.ao_spp = 1;
    rs.seed = 2;
    return render::render_view(rt, cam, rs, 1);
  }();
  return v;
}

}  // namespace nns::testing
