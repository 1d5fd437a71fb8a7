#pragma once
// Checks every generation of procedural families must pass (test_render_families_v*.cpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "render/placement.h"
#include "render/render_view.h"
#include "render/scenes/families.h"

namespace nns::testing {

// The family's first instance renders a lit view whose light is not all direct: there
// is indirect light to learn, and occlusion.
inline void expect_lit_view_with_indirect_light(const std::string& name) {
  using namespace nns::data;
  using namespace nns::render;
  Scene s = make_family_scene(name, 0, 8);
  RayTracer rt(s);
  Rng rng(4);
  Camera cam = place_camera(rt, 24, 24, 90, rng);
  RenderSettings rs;
  rs.ao_spp = 8, rs.gi_spp = 16, rs.light_spp = 1, rs.seed = 2;
  rs.lighting = true, rs.indirect = true;
  View v = render_view(rt, cam, rs, 1);
  double direct = 0, indirect = 0, ao = 0;
  int geo = 0;
  for (size_t i = 0; i < v.channel("Z").size(); ++i) {
    if (is_sky(v.channel("Z")[i])) continue;
    ++geo;
    direct += v.channel("direct.G")[i], indirect += v.channel("indirect.G")[i], ao += v.channel("AO")[i];
  }
  ASSERT_GT(geo, 0) << name;
  EXPECT_GT(indirect / geo, 0.01) << name << ": no indirect light";
  EXPECT_LT(ao / geo, 0.98) << name << ": nothing occluded";
  std::printf("%-10s direct %.3f indirect %.3f AO %.3f per geometry pixel\n", name.c_str(), direct / geo,
              indirect / geo, ao / geo);
}

}  // namespace nns::testing
