// Scene families, camera placement and paths, surround capture geometry, the AO noise
// level, and mesh loading.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <tuple>

#include "render/placement.h"
#include "render/surround.h"
#include "render/scenes/builder.h"
#include "render/scenes/families.h"
#include "render/scenes/mesh_loader.h"
#include "render/scenes/scene_variation.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;

TEST(SceneFamilies, DeterministicDistinctAndPlaceable) {
  for (const SceneFamily& f : scene_families()) {
    Scene a = make_family_scene(f.name, 0, 7), b = make_family_scene(f.name, 0, 7), c = make_family_scene(f.name, 1, 7);
    ASSERT_GT(a.triangles.size(), 10u) << f.name;
    EXPECT_EQ(a.name, f.name + "-0");
    ASSERT_EQ(a.positions.size(), b.positions.size()) << f.name;
    for (size_t i = 0; i < a.positions.size(); ++i) ASSERT_EQ(a.positions[i].x, b.positions[i].x) << f.name;
    EXPECT_TRUE(a.positions.size() != c.positions.size() || a.positions[5].x != c.positions[5].x) << f.name;
    EXPECT_FALSE(a.suns.empty() && a.points.empty() && a.rects.empty()) << f.name << " has no light";
    RayTracer rt(a);
    Rng rng(3);
    Camera cam = place_camera(rt, 64, 36, 60, rng);
    ProbeResult p = probe_view(rt, cam);
    EXPECT_TRUE(acceptable(p, {})) << f.name << ": sky " << p.sky_fraction << " plane " << p.plane_fraction
                                   << " median depth " << p.median_depth << " nearest " << p.nearest;
  }
  EXPECT_THROW(scene_family("nope"), std::invalid_argument);
}

TEST(Placement, RejectsSkyAndFlatWall) {
  Scene s;
  s.name = "wall";
  uint32_t m = s.add_material({});
  add_quad(s, {-50, 0, -50}, {100, 0, 0}, {0, 0, 100}, m);
  add_quad(s, {-50, 0, -3}, {100, 0, 0}, {0, 30, 0}, m);
  RayTracer rt(s);
  Camera sky = Camera::from_yaw_pitch({0, 1.5f, 0}, 3.14159f, 0.6f);  // away from the wall, up
  sky.width = 32, sky.height = 18;
  EXPECT_GT(probe_view(rt, sky).sky_fraction, 0.5f);
  EXPECT_FALSE(acceptable(probe_view(rt, sky), {}));
  Camera wall = Camera::from_yaw_pitch({0, 1.5f, 0}, 0, 0.2f);  // straight at the wall
  wall.width = 32, wall.height = 18;
  EXPECT_GT(probe_view(rt, wall).plane_fraction, 0.6f);
  EXPECT_FALSE(acceptable(probe_view(rt, wall), {}));
}

TEST(Placement, CameraPathIsSmoothAndFree) {
  Scene s = make_family_scene("room", 0, 11);
  RayTracer rt(s);
  Rng rng(5);
  auto path = camera_path(rt, 32, 18, 60, 12, rng);
  ASSERT_EQ(path.size(), 12u);
  for (size_t i = 1; i < path.size(); ++i) {
    Vec3 step = path[i].eye - path[i - 1].eye;
    EXPECT_LT(length(step), 0.12f);
    EXPECT_GT(dot(path[i].forward(), path[i - 1].forward()), 0.995f);  // < ~6 degrees per frame
    float len = length(step);
    if (len > 0) {
      EXPECT_FALSE(rt.occluded(path[i - 1].eye, step / len, 0, len));
    }
  }
}

TEST(Surround, FaceOrientationsFollowTheSpec) {
  Camera front = Camera::from_yaw_pitch({1, 2, 3}, 0.4f, 0.1f);
  auto faces = cube_face_cameras(front, 8);
  auto fwd = [](const Camera& c) { return c.forward(); };
  auto near = [](Vec3 a, Vec3 b) { return length(a - b) < 1e-5f; };
  EXPECT_TRUE(near(fwd(faces[0]), front.forward()));
  EXPECT_TRUE(near(fwd(faces[1]), front.back));                               // back looks +z
  EXPECT_TRUE(near(fwd(faces[2]), -front.right));                             // left looks -x
  EXPECT_TRUE(near(fwd(faces[3]), front.right));                              // right looks +x
  EXPECT_TRUE(near(fwd(faces[4]), front.up));                                 // up looks +y
  EXPECT_TRUE(near(fwd(faces[5]), -front.up));                                // down looks -y
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(near(faces[i].up, front.up)) << i;  // yawed faces keep up
  EXPECT_TRUE(near(faces[4].up, front.back));                                 // up: image up towards the back (+z)
  EXPECT_TRUE(near(faces[5].up, -front.back));                                // down: image up -z
  for (auto& c : faces) {
    EXPECT_TRUE(near(cross(c.right, c.up), c.back));  // right-handed
    EXPECT_EQ(c.fov_y_deg, 90.0f);
    EXPECT_TRUE(near(c.eye, front.eye));
  }
  // Adjacent faces share their edges (ndc = +-1): front's right edge is right's left
  // edge, front's top edge is up's bottom edge, front's bottom edge is down's top edge.
  auto dir = [](const Camera& c, float xn, float yn) { return c.right * xn + c.up * yn - c.back; };
  EXPECT_TRUE(near(dir(faces[0], 1, 0.3f), dir(faces[3], -1, 0.3f)));
  EXPECT_TRUE(near(dir(faces[0], -1, 0.3f), dir(faces[2], 1, 0.3f)));
  EXPECT_TRUE(near(dir(faces[0], 0.4f, 1), dir(faces[4], 0.4f, -1)));
  EXPECT_TRUE(near(dir(faces[0], 0.4f, -1), dir(faces[5], 0.4f, 1)));
  EXPECT_TRUE(near(dir(faces[3], 1, 0.2f), dir(faces[1], -1, 0.2f)));
}

// Over an infinite floor, every face's normals are the floor normal in the FRONT
// camera's space, and the down face sees the floor at planar depth = eye height.
TEST(Surround, NormalsInFrontSpaceAndOwnPlanarDepth) {
  Scene s;
  s.name = "floor";
  uint32_t m = s.add_material({});
  add_quad(s, {-1000, 0, -1000}, {2000, 0, 0}, {0, 0, 2000}, m);
  s.sky = Sky::constant({1, 1, 1});
  RayTracer rt(s);
  Camera front = Camera::from_yaw_pitch({0, 1.7f, 0}, 0.7f, 0);  // level: down faces the floor
  RenderSettings rs;
  rs.ao_spp = 4, rs.gi_spp = 2;
  auto views = render_surround(rt, front, 16, rs, 0);
  Vec3 n = front.to_camera({0, 1, 0});
  for (int f = 0; f < 6; ++f) {
    const View& v = views[size_t(f)];
    EXPECT_EQ(v.width, 16);
    EXPECT_EQ(v.has("indirect.R"), f == 0) << f;
    EXPECT_TRUE(v.has("direct.R") && v.has("env.R") && v.has("AO")) << f;
    for (size_t i = 0; i < v.channel("Z").size(); ++i)
      if (!is_sky(v.channel("Z")[i])) {
        EXPECT_NEAR(v.channel("N.Y")[i], n.y, 1e-5) << f;
      }
  }
  for (float z : views[5].channel("Z")) EXPECT_NEAR(z, 1.7f, 1e-4);
  for (float z : views[4].channel("Z")) EXPECT_TRUE(is_sky(z));
}

// The Monte-Carlo noise of AO at the default 256 spp, measured as the standard
// deviation of one estimate from the difference of two independent renders
// (std(a - b) / sqrt(2)), over the geometry pixels of a furnished room.
TEST(RenderNoise, AOAtDefaultSppIsWellBelowSSAOErrors) {
  Scene s = make_family_scene("room", 0, 1);
  RayTracer rt(s);
  Rng rng(2);
  Camera cam = place_camera(rt, 80, 45, 60, rng);
  RenderSettings a, b;
  a.lighting = b.lighting = false;
  a.seed = 1, b.seed = 2;
  View va = render_view(rt, cam, a, 0), vb = render_view(rt, cam, b, 0);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (size_t i = 0; i < va.channel("AO").size(); ++i) {
    if (is_sky(va.channel("Z")[i])) continue;
    double d = double(va.channel("AO")[i]) - vb.channel("AO")[i];
    sum += d, sum2 += d * d, ++n;
  }
  ASSERT_GT(n, 1000);
  double noise_std = std::sqrt(sum2 / n / 2);
  std::printf("AO noise at 256 spp: std %.4f, MSE %.2e (mean difference %.1e)\n", noise_std, noise_std * noise_std,
              sum / n);
  EXPECT_LT(noise_std, 0.02);  // MSE < 4e-4, vs SSAO errors of 1e-2..1e-1
  EXPECT_GT(noise_std, 0.0);   // the two seeds really are independent
}

// The noise of the GI target in the hardest family (sunlit patches off-screen, found
// only by the few paths that hit them), as a fraction of the mean indirect light.
TEST(RenderNoise, IndirectInWindowRoom) {
  Scene s = make_family_scene("window-room", 0, 1);
  RayTracer rt(s);
  Rng rng(4);
  Camera cam = place_camera(rt, 32, 32, 90, rng);
  for (int spp : {64, 256}) {
    RenderSettings a, b;
    a.ao = b.ao = false;
    a.gi_spp = b.gi_spp = spp;
    a.seed = 1, b.seed = 2;
    View va = render_view(rt, cam, a, 0), vb = render_view(rt, cam, b, 0);
    double mean = 0, d2 = 0;
    int n = 0;
    for (const char* c : {"indirect.R", "indirect.G", "indirect.B"})
      for (size_t i = 0; i < va.channel(c).size(); ++i) {
        if (is_sky(va.channel("Z")[i])) continue;
        double d = double(va.channel(c)[i]) - vb.channel(c)[i];
        mean += 0.5 * (va.channel(c)[i] + vb.channel(c)[i]), d2 += d * d, ++n;
      }
    mean /= n;
    double rel = std::sqrt(d2 / n / 2) / mean;
    std::printf("indirect noise at %d paths: std %.3f of mean %.3f (%.1f%%)\n", spp, rel * mean, mean, 100 * rel);
    EXPECT_LT(rel, spp == 256 ? 0.15 : 0.35);
  }
}

namespace {
std::string temp_path(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("nnshade-render-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

// A glTF data URI's payload (the byte count a multiple of 3 here: no padding).
std::string base64(const void* data, size_t n) {
  const unsigned char* bytes = static_cast<const unsigned char*>(data);
  static const char* b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string enc;
  for (size_t i = 0; i + 2 < n; i += 3) {
    uint32_t v = uint32_t(bytes[i]) << 16 | uint32_t(bytes[i + 1]) << 8 | bytes[i + 2];
    for (int k = 3; k >= 0; --k) enc += b64[(v >> (6 * k)) & 63];
  }
  return enc;
}

// Removes this process's temporary folder after the last test.
class RemoveTempDir : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignore;
    std::filesystem::remove_all(
        std::filesystem::temp_directory_path() / ("nnshade-render-test-" + std::to_string(::getpid())), ignore);
  }
};
const auto* const kRemoveTempDir = ::testing::AddGlobalTestEnvironment(new RemoveTempDir);
}  // namespace

TEST(MeshLoader, ObjWithMaterials) {
  std::string obj = temp_path("quad.obj"), mtl = temp_path("quad.mtl");
  std::ofstream(mtl) << "newmtl red\nKd 0.8 0.1 0.1\nKe 0 0 0\nnewmtl glow\nKd 0.5 0.5 0.5\nKe 2 2 1\n";
  std::ofstream(obj) << "mtllib quad.mtl\nv -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nv 0 1 0\n"
                        "usemtl red\nf 1 2 3 4\nusemtl glow\nf 1 2 5\n";
  Scene s = load_mesh_scene(obj);
  EXPECT_EQ(s.name, "quad");
  ASSERT_EQ(s.triangles.size(), 3u);
  EXPECT_NEAR(s.materials[s.triangles[0].material].albedo.x, 0.8f, 1e-6);
  EXPECT_NEAR(s.materials[s.triangles[2].material].emission.x, 2.0f, 1e-6);
  EXPECT_FALSE(s.suns.empty());
  RayTracer rt(s);
  EXPECT_TRUE(rt.intersect({0, 3, 0.5f}, {0, -1, 0}).valid());
}

TEST(MeshLoader, GltfWithNodeTransform) {
  // One triangle (3 float positions, no indices) under a node translated by +2 in y.
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 0, 1};
  const std::string enc = base64(pos, sizeof pos);
  auto write = [&](const std::string& path, int count) {
    std::ofstream(path) << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
                        << R"("nodes":[{"mesh":0,"translation":[0,2,0]}],)"
                        << R"("materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.4,0.6,1]}}],)"
                        << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],)"
                        << R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" << count
                        << R"(,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}],)"
                        << R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
                        << R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)" << enc
                        << R"("}]})";
  };
  std::string path = temp_path("tri.gltf"), bad = temp_path("bad.gltf");
  write(path, 3);
  write(bad, 6);  // an accessor that reads past its buffer: an error naming the file
  try {
    load_mesh_scene(bad);
    ADD_FAILURE() << "no error for an accessor past its buffer";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.gltf"), std::string::npos) << e.what();
  }
  Scene s = load_mesh_scene(path);
  ASSERT_EQ(s.triangles.size(), 1u);
  EXPECT_NEAR(s.positions[s.triangles[0].v[1]].x, 1.0f, 1e-6);
  EXPECT_NEAR(s.positions[s.triangles[0].v[1]].y, 2.0f, 1e-6);
  EXPECT_NEAR(s.materials[s.triangles[0].material].albedo.y, 0.4f, 1e-6);
}

TEST(MeshLoader, ErrorsNameTheFile) {
  try {
    load_mesh_scene("/nonexistent/scene.obj");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.obj"), std::string::npos);
  }
  std::string txt = temp_path("scene.txt");
  std::ofstream(txt) << "hello";
  try {
    load_mesh_scene(txt);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported"), std::string::npos) << e.what();
  }
  std::string empty = temp_path("empty.obj");
  std::ofstream(empty) << "# nothing\n";
  EXPECT_THROW(load_mesh_scene(empty), std::runtime_error);
}

// An OBJ with a NaN vertex rendered all-zero depth and exited 0.
TEST(MeshLoader, NonFiniteVerticesAreRefusedNamingTheFile) {
  for (const char* bad : {"nan", "inf", "-inf", "1e40"}) {
    std::string obj = temp_path(std::string("bad-") + bad + ".obj");
    std::ofstream(obj) << "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv " << bad << " 0 5\nf 1 2 3\nf 1 3 4\n";
    try {
      load_mesh_scene(obj);
      ADD_FAILURE() << "no error for a vertex coordinate '" << bad << "'";
    } catch (const std::runtime_error& e) {
      std::string m = e.what();
      EXPECT_NE(m.find(obj + ": "), std::string::npos) << m;
      EXPECT_NE(m.find("non-finite"), std::string::npos) << m;
    }
  }
  // A glTF node scale of 1e39 overflows float when applied.
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 0, 1};
  const std::string enc = base64(pos, sizeof pos);
  std::string gltf = temp_path("huge.gltf");
  std::ofstream(gltf)
      << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
      << R"("nodes":[{"mesh":0,"scale":[1e39,1,1]}],)"
      << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
      << R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}],)"
      << R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
      << R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)" << enc << R"("}]})";
  try {
    load_mesh_scene(gltf);
    ADD_FAILURE() << "no error for a non-finite transformed vertex";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(gltf + ": "), std::string::npos) << e.what();
  }
}

// Found by fuzz/fuzz_scene.cpp (fuzz/regressions/scene/gltf-float-indices): a primitive
// whose indices were a float accessor had each float converted to an integer, out of
// range and undefined; an index past the primitive's vertices pointed into another's.
TEST(MeshLoader, GltfTriangleIndicesAreUnsignedAndInsideTheirPrimitive) {
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 0, 1};
  unsigned char buf[42];  // 3 float vertices, then 3 uint16 indices
  std::memcpy(buf, pos, sizeof pos);
  auto write = [&](const std::string& name, int index_type, uint16_t last) {
    const uint16_t idx[3] = {0, 1, last};
    std::memcpy(buf + sizeof pos, idx, sizeof idx);
    const std::string p = temp_path(name);
    std::ofstream(p) << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
                     << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
                     << R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                     << R"({"bufferView":)" << (index_type == 5126 ? 0 : 1) << R"(,"componentType":)" << index_type
                     << R"(,"count":3,"type":"SCALAR"}],)"
                     << R"("bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],)"
                     << R"("buffers":[{"byteLength":42,"uri":"data:application/octet-stream;base64,)"
                     << base64(buf, sizeof buf) << R"("}]})";
    return p;
  };
  EXPECT_EQ(load_mesh_scene(write("ok.gltf", 5123, 2)).triangles.size(), 1u);
  for (auto [name, type, last, what] : {std::tuple{"float-indices.gltf", 5126, 2, "not unsigned integers"},
                                        std::tuple{"index-past.gltf", 5123, 3, "past its primitive's 3 vertices"}}) {
    const std::string p = write(name, type, uint16_t(last));
    try {
      load_mesh_scene(p);
      ADD_FAILURE() << "no error for " << name;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(p + ": "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  }
}

// Found by fuzz/fuzz_scene.cpp: a glTF node listed among its own children recursed until
// the stack overflowed. glTF nodes form a forest (one parent at most); a node reached
// twice would also multiply the work of every shared subtree.
TEST(MeshLoader, GltfNodeHierarchyMustBeAForest) {
  auto write = [](const std::string& path, const std::string& nodes) {
    std::ofstream(path)
        << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":)" << nodes
        << R"(,"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
        << R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}],)"
        << R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
        << R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)"
        << R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIA/"}]})";
  };
  for (const char* nodes : {R"([{"mesh":0,"children":[0]}])", R"([{"mesh":0,"children":[1]},{"children":[0]}])",
                            R"([{"mesh":0,"children":[1,1]},{"mesh":0}])"}) {
    std::string path = temp_path("cycle.gltf");
    write(path, nodes);
    try {
      load_mesh_scene(path);
      ADD_FAILURE() << "accepted " << nodes;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("node"), std::string::npos) << e.what();
    }
  }
  std::string ok = temp_path("tree.gltf");
  write(ok, R"([{"mesh":0,"children":[1]},{"mesh":0}])");
  EXPECT_EQ(load_mesh_scene(ok).triangles.size(), 2u);
}

// Found by fuzz/fuzz_scene.cpp: a buffer whose uri names a directory was sized by
// tinygltf as 2^63 - 1 bytes and the allocation aborted the process. It is an error
// naming the file now; a buffer in a regular file next to the glTF still loads.
TEST(MeshLoader, GltfBufferUriMustBeARegularFile) {
  const std::string dir = temp_path("gltf-uri");
  std::filesystem::create_directories(dir + "/folder");
  auto write = [&](const std::string& path, const std::string& uri) {
    std::ofstream(path)
        << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}])"
        << R"(,"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
        << R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}],)"
        << R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
        << R"("buffers":[{"byteLength":36,"uri":")" << uri << R"("}]})";
  };
  const std::string bad = dir + "/dir-uri.gltf";
  write(bad, "folder");
  try {
    load_mesh_scene(bad);
    ADD_FAILURE() << "accepted a buffer uri naming a directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad + ": "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
  // The same 36 bytes in a file beside the glTF.
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::ofstream(dir + "/tri.bin", std::ios::binary).write(reinterpret_cast<const char*>(tri), sizeof tri);
  const std::string ok = dir + "/file-uri.gltf";
  write(ok, "tri.bin");
  EXPECT_EQ(load_mesh_scene(ok).triangles.size(), 1u);
}

// surround-v2's per-scene variation: the same seed gives the same scene; albedos stay
// physical (< 0.9) and change; emissive materials keep their albedo; suns stay in the
// elevation range; extra lamps stand inside the camera region.
TEST(SceneVariation, DeterministicPhysicalAndInsideTheCameraRegion) {
  using namespace nns::data;
  LightingVariation v;
  int lamps_seen = 0, coloured = 0;
  for (const char* family : {"room", "window-room", "lounge", "street"}) {
    for (uint64_t seed = 1; seed <= 6; ++seed) {
      const Scene base = make_family_scene(family, 0, 7);
      Scene a = base, b = base;
      nns::Rng ra(seed), rb(seed);
      vary_materials_and_lights(a, ra, v);
      vary_materials_and_lights(b, rb, v);
      ASSERT_EQ(a.materials.size(), b.materials.size());
      for (size_t i = 0; i < a.materials.size(); ++i) {
        EXPECT_EQ(a.materials[i].albedo.x, b.materials[i].albedo.x);
        const Vec3 al = a.materials[i].albedo, em = base.materials[i].emission;
        if (em.x > 0 || em.y > 0 || em.z > 0) {
          EXPECT_EQ(al.x, base.materials[i].albedo.x) << family << ": an emissive material's albedo moved";
          continue;
        }
        for (float c : {al.x, al.y, al.z}) EXPECT_TRUE(c >= 0 && c < 0.9f) << family << " albedo " << c;
        if (std::max({al.x, al.y, al.z}) > 1.5f * std::min({al.x, al.y, al.z}) + 0.02f) ++coloured;
      }
      ASSERT_EQ(a.suns.size(), base.suns.size());
      for (const Sun& s : a.suns) {
        const float el = std::asin(s.direction.y) * 180 / float(M_PI);
        EXPECT_GE(el, v.sun_elevation_min - 1e-3f);
        EXPECT_LE(el, v.sun_elevation_max + 1e-3f);
        EXPECT_GE(s.angular_radius, v.sun_radius_min * 0.999f);
      }
      for (size_t k = base.points.size(); k < a.points.size(); ++k, ++lamps_seen) {
        const Vec3 p = a.points[k].position;
        EXPECT_TRUE(p.x >= a.cameras.min.x && p.x <= a.cameras.max.x && p.y >= a.cameras.min.y &&
                    p.y <= a.cameras.max.y && p.z >= a.cameras.min.z && p.z <= a.cameras.max.z)
            << family << ": lamp outside the camera region";
      }
    }
  }
  EXPECT_GT(lamps_seen, 4);  // lamp_share 0.6 over 24 scenes
  EXPECT_GT(coloured, 10);   // colour_share 0.4 over every material
}
