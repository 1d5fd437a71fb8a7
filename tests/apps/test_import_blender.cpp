// Runs the built `import-blender` on a synthetic EXR named the way Blender names its
// multilayer passes, and checks the conversion pixel by pixel.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include "core/folder_lock.h"
#include "data/exr_io.h"
#include "tests/support/run_command.h"

using namespace nns::data;
namespace fs = std::filesystem;

namespace {

using Outcome = nns::testing::CommandResult;

Outcome run(const std::string& binary, const std::string& args) { return nns::testing::run_app(binary, args); }

// The camera looks along world +Y with world +Z up (Blender's usual set-up): camera
// space (x, y, z) = (x_w, z_w, -y_w), plus a translation that normals must ignore.
const char* kWorldToCamera = "1,0,0,5, 0,0,1,-2, 0,-1,0,7, 0,0,0,1";

// 4x2 pixels: 0 sky (Cycles' 1e10), 1 floor (normal +Z world), 2 wall facing the camera
// (normal -Y world), 3 background written as 0, 4-7 a wall facing +X.
View blender_view(const std::string& layer) {
  View v;
  v.width = 4;
  v.height = 2;
  v.scene = "";  // Blender writes no such attribute
  auto name = [&](const std::string& s) { return layer + "." + s; };
  auto& z = v.add_channel(name("Depth.Z"));
  auto &nx = v.add_channel(name("Normal.X")), &ny = v.add_channel(name("Normal.Y")),
       &nz = v.add_channel(name("Normal.Z"));
  for (const char* p : {"DiffCol", "DiffDir", "DiffInd", "Emit", "Env", "AO"})
    for (const char* c : {"R", "G", "B"}) v.add_channel(name(std::string(p) + "." + c));
  v.add_channel(name("Combined.R"));
  for (int i = 0; i < 8; ++i) {
    z[size_t(i)] = 2.0f + float(i);
    nx[size_t(i)] = 1;
    v.channels[name("DiffCol.G")][size_t(i)] = 0.25f;
    v.channels[name("DiffDir.R")][size_t(i)] = 3.0f;
    v.channels[name("DiffInd.B")][size_t(i)] = 0.5f;
    v.channels[name("AO.R")][size_t(i)] = v.channels[name("AO.G")][size_t(i)] = 0.125f * float(i);
  }
  z[0] = 1e10f;
  nx[0] = 0;
  nx[1] = 0, nz[1] = 1;
  nx[2] = 0, ny[2] = -1;
  z[3] = 0;
  nx[3] = 0;
  return v;
}

// As Blender writes it: no nnshade attributes, the render stamp "Note" as a string.
void write_with_note(const std::string& path, const View& v, const std::string& note) {
  Imf::Header h(v.width, v.height);
  h.insert("Note", Imf::StringAttribute(note));
  Imf::FrameBuffer fb;
  for (auto& [name, plane] : v.channels) {
    h.channels().insert(name, Imf::Channel(Imf::FLOAT));
    fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(plane.data())), 4,
                               4 * size_t(v.width)));
  }
  Imf::OutputFile out(path.c_str(), h);
  out.setFrameBuffer(fb);
  out.writePixels(v.height);
}

// What tools/blender_capture.py writes for the kWorldToCamera camera.
std::string capture_note(const std::string& extra = "") {
  return std::string("nnshade-camera 1\nfovY=33.5\nworldToCamera=") + kWorldToCamera +
         "\naoRadius=0.75\nscene=room\ncamera=Cam" + extra;
}

struct Dir {
  fs::path path;
  Dir() {
    path = fs::temp_directory_path() / ("nns_test_import_blender_" + std::to_string(getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Dir() { fs::remove_all(path); }
  std::string operator/(const std::string& s) const { return (path / s).string(); }
};

}  // namespace

TEST(ImportBlender, ConvertsPassesAndRotatesNormalsIntoCameraSpace) {
  Dir d;
  write_view(d / "render.exr", blender_view("ViewLayer"));
  Outcome r =
      run("import-blender", "--fov-y 40 --ao-radius 0.5 --scene barn --world-to-camera \"" +
                                std::string(kWorldToCamera) + "\" --out " + (d / "out.exr") + " " + (d / "render.exr"));
  ASSERT_EQ(r.code, 0) << r.output;
  View v = read_view(d / "out.exr");
  EXPECT_EQ(v.scene, "barn");
  EXPECT_FLOAT_EQ(v.fov_y_deg, 40);
  ASSERT_TRUE(v.ao_radius.has_value());
  EXPECT_FLOAT_EQ(*v.ao_radius, 0.5f);
  // Depth: planar already; sky (1e10 and 0) becomes +inf.
  EXPECT_TRUE(std::isinf(v.at("Z", 0, 0)));
  EXPECT_TRUE(std::isinf(v.at("Z", 3, 0)));
  EXPECT_EQ(v.at("Z", 1, 0), 3.0f);
  // Normals: floor -> up (+y), wall facing the camera -> +z, +X wall -> +x; sky zero.
  EXPECT_NEAR(v.at("N.Y", 1, 0), 1, 1e-6);
  EXPECT_NEAR(v.at("N.Z", 2, 0), 1, 1e-6);
  EXPECT_NEAR(v.at("N.X", 0, 1), 1, 1e-6);
  EXPECT_EQ(v.at("N.X", 0, 0), 0);
  EXPECT_EQ(v.at("N.Z", 0, 0), 0);
  // Light and material passes under their spec names; Env only on request.
  EXPECT_EQ(v.at("albedo.G", 2, 1), 0.25f);
  EXPECT_EQ(v.at("direct.R", 2, 1), 3.0f);
  EXPECT_EQ(v.at("indirect.B", 2, 1), 0.5f);
  EXPECT_TRUE(v.has("emission.R"));
  EXPECT_FALSE(v.has("env.R"));
  EXPECT_FALSE(v.has("ViewLayer.Combined.R"));
  EXPECT_EQ(v.at("AO", 1, 1), 0.625f);
  ASSERT_TRUE(v.world_to_camera.has_value());
  EXPECT_EQ((*v.world_to_camera)[3], 5.0f);
}

TEST(ImportBlender, ConvertedDatasetValidatesClean) {
  Dir d;
  write_view(d / "a.exr", blender_view("ViewLayer"));
  std::string common = "--fov-y 50 --ao-radius 1 --world-to-camera \"" + std::string(kWorldToCamera) + "\" ";
  ASSERT_EQ(run("import-blender", common + "--scene one --out " + (d / "ds/train") + " " + (d / "a.exr")).code, 0);
  ASSERT_EQ(run("import-blender", common + "--scene two --out " + (d / "ds/test") + " " + (d / "a.exr")).code, 0);
  Outcome info = run("dataset-info", "--purpose nnao " + (d / "ds"));
  EXPECT_EQ(info.code, 0) << info.output;
}

TEST(ImportBlender, ExplainsWhatIsMissing) {
  Dir d;
  write_view(d / "r.exr", blender_view("ViewLayer"));
  Outcome no_fov = run("import-blender", "--out " + (d / "o.exr") + " " + (d / "r.exr"));
  EXPECT_EQ(no_fov.code, 1);
  EXPECT_NE(no_fov.output.find(d / "r.exr" + ": no field of view: render with tools/blender_capture.py"),
            std::string::npos)
      << no_fov.output;

  Outcome no_cam = run("import-blender", "--fov-y 40 --ao-radius 1 --out " + (d / "o.exr") + " " + (d / "r.exr"));
  EXPECT_EQ(no_cam.code, 1);
  EXPECT_NE(no_cam.output.find(d / "r.exr" + ": world-space normals need the camera"), std::string::npos)
      << no_cam.output;

  Outcome no_radius = run("import-blender", "--fov-y 40 --world-to-camera \"" + std::string(kWorldToCamera) +
                                                "\" --out " + (d / "o.exr") + " " + (d / "r.exr"));
  EXPECT_EQ(no_radius.code, 1);
  EXPECT_NE(no_radius.output.find("--ao-radius"), std::string::npos) << no_radius.output;
  // Where Blender 3.x keeps the distance (the old message sent users to a panel that does not exist).
  EXPECT_NE(no_radius.output.find("Light Paths > Fast GI Approximation > AO Distance, world.light_settings.distance"),
            std::string::npos)
      << no_radius.output;

  View two = blender_view("ViewLayer");
  for (auto& [name, plane] : blender_view("Other").channels) two.channels[name] = plane;
  write_view(d / "two.exr", two);
  Outcome layers = run("import-blender", "--fov-y 40 --out " + (d / "o.exr") + " " + (d / "two.exr"));
  EXPECT_EQ(layers.code, 1);
  EXPECT_NE(layers.output.find("several view layers (Other, ViewLayer); choose one with --layer"), std::string::npos)
      << layers.output;
  EXPECT_FALSE(fs::exists(d / "o.exr"));
}

TEST(ImportBlender, TakesTheCameraFromTheCaptureNote) {
  Dir d;
  fs::create_directories(d / "capture/Cam-surround");
  write_with_note(d / "capture/Cam.exr", blender_view("ViewLayer"), capture_note());
  write_with_note(d / "capture/Cam-surround/front.exr", blender_view("ViewLayer"), capture_note());
  // No camera flags: a folder input is converted whole, sub-folders kept.
  Outcome r = run("import-blender", "--out " + (d / "ds/train") + " " + (d / "capture"));
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* name : {"ds/train/Cam.exr", "ds/train/Cam-surround/front.exr"}) {
    View v = read_view(d / name);
    EXPECT_FLOAT_EQ(v.fov_y_deg, 33.5f) << name;
    EXPECT_EQ(v.scene, "room") << name;
    ASSERT_TRUE(v.ao_radius.has_value());
    EXPECT_FLOAT_EQ(*v.ao_radius, 0.75f);
    EXPECT_NEAR(v.at("N.Z", 2, 0), 1, 1e-6) << name;  // the note's matrix rotated the normals
  }
  // A flag given by hand wins, and says so.
  Outcome over = run("import-blender", "--fov-y 50 --out " + (d / "o.exr") + " " + (d / "capture/Cam.exr"));
  ASSERT_EQ(over.code, 0) << over.output;
  EXPECT_NE(over.output.find("--fov-y given by hand overrides the file's capture note"), std::string::npos)
      << over.output;
  EXPECT_FLOAT_EQ(read_view(d / "o.exr").fov_y_deg, 50.0f);
}

TEST(ImportBlender, RefusesAMalformedCaptureNoteNamingTheFile) {
  Dir d;
  const std::string good_matrix = std::string("worldToCamera=") + kWorldToCamera;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"nnshade-camera 2\nfovY=40", "is not 'nnshade-camera 1'"},
      {"nnshade-camera 1\nfovY=40\naoRadius=1", "needs fovY, worldToCamera and aoRadius"},
      {"nnshade-camera 1\nfovY=nan\naoRadius=1\n" + good_matrix, "fovY must be degrees in (0, 180)"},
      {"nnshade-camera 1\nfovY=200\naoRadius=1\n" + good_matrix, "fovY must be degrees"},
      {"nnshade-camera 1\nfovY=40\naoRadius=-1\n" + good_matrix, "aoRadius must be a positive number"},
      {"nnshade-camera 1\nfovY=40\naoRadius=1\nworldToCamera=1,2,3", "expected 16 comma-separated finite numbers"},
      {"nnshade-camera 1\nfovY=40\naoRadius=1\nworldToCamera=1x,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1", "expected 16"},
      {"nnshade-camera 1\nfovY=40\nfovY=41\naoRadius=1\n" + good_matrix, "'fovY' given twice"},
      {"nnshade-camera 1\nfovY 40", "line without '='"},
  };
  for (auto& [note, message] : cases) {
    write_with_note(d / "r.exr", blender_view("ViewLayer"), note);
    Outcome r = run("import-blender", "--out " + (d / "out") + " " + (d / "r.exr"));
    EXPECT_EQ(r.code, 1) << note;
    EXPECT_NE(r.output.find(d / "r.exr" + ": Note (written by tools/blender_capture.py): "), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << note << "\n" << r.output;
    EXPECT_FALSE(fs::exists(d / "out/r.exr"));
  }
  // Someone's own note is not a capture note: the flags are needed, as without one.
  write_with_note(d / "r.exr", blender_view("ViewLayer"), "lit by the window");
  Outcome own = run("import-blender", "--out " + (d / "out") + " " + (d / "r.exr"));
  EXPECT_EQ(own.code, 1);
  EXPECT_NE(own.output.find("no field of view"), std::string::npos) << own.output;
  // Hand-given matrices are as strict as the note's.
  Outcome junk = run("import-blender", "--fov-y 40 --world-to-camera \"1x,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1\" --out " +
                                           (d / "out") + " " + (d / "r.exr"));
  EXPECT_EQ(junk.code, 1);
  EXPECT_NE(junk.output.find("--world-to-camera: expected 16 comma-separated finite numbers"), std::string::npos)
      << junk.output;
}

// NaN, -inf and negative depth became sky, a NaN normal (0, 0, 0), and a world-to-camera
// of 16 zeros made every normal zero; each exited 0 with views dataset-info rejects.
TEST(ImportBlender, RefusesBrokenDepthAndNormalsNamingFilePassAndPixel) {
  Dir d;
  const std::string flags = "--fov-y 40 --ao-radius 0.5 --world-to-camera \"" + std::string(kWorldToCamera) + "\" ";
  struct Broken {
    const char* pass;
    float value;
    const char* expect;
  };
  for (const Broken& b : {Broken{"Depth.Z", NAN, "pass ViewLayer.Depth.Z, pixel (2, 1)"},
                          Broken{"Depth.Z", -INFINITY, "pass ViewLayer.Depth.Z, pixel (2, 1)"},
                          Broken{"Depth.Z", -1.5f, "pass ViewLayer.Depth.Z, pixel (2, 1)"},
                          Broken{"Normal.Y", NAN, "pass ViewLayer.Normal.Y, pixel (2, 1)"}}) {
    View v = blender_view("ViewLayer");
    v.channels[std::string("ViewLayer.") + b.pass][6] = b.value;
    const std::string in = d / "broken.exr", out = d / "out.exr";
    write_view(in, v);
    Outcome r = run("import-blender", flags + "--out " + out + " " + in);
    EXPECT_EQ(r.code, 1) << b.pass << " " << b.value << "\n" << r.output;
    EXPECT_NE(r.output.find(in), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(b.expect), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << b.pass << " " << b.value;
  }
  write_view(d / "render.exr", blender_view("ViewLayer"));
  Outcome r =
      run("import-blender", "--fov-y 40 --ao-radius 0.5 --world-to-camera \"0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\" --out " +
                                (d / "out.exr") + " " + (d / "render.exr"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find(d / "render.exr"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("world-to-camera"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out.exr"));
}

// A folder output is locked while the import runs: a second command writing the same
// folder is refused, naming it, and writes nothing.
TEST(ImportBlender, AFolderAnotherProcessWritesIsRefused) {
  Dir d;
  write_view(d / "a.exr", blender_view("ViewLayer"));
  fs::create_directories(d / "ds");
  nns::FolderLock held(d / "ds", "render-dataset");
  std::string common = "--fov-y 50 --ao-radius 1 --world-to-camera \"" + std::string(kWorldToCamera) + "\" ";
  Outcome r = run("import-blender", common + "--scene one --out " + (d / "ds") + " " + (d / "a.exr"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("ds"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("in use by another run (pid " + std::to_string(::getpid())), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(fs::path(d / "ds") / "a.exr"));
}

// A folder of renders whose second file is broken used to leave the first one converted
// in the output folder: half an import. Now a failed import leaves nothing it wrote.
TEST(ImportBlender, ABrokenFileAmongSeveralLeavesNothing) {
  Dir d;
  fs::create_directories(d / "renders");
  write_view(d / "renders/a.exr", blender_view("ViewLayer"));
  View broken = blender_view("ViewLayer");
  broken.channels["ViewLayer.Depth.Z"][6] = NAN;
  write_view(d / "renders/b.exr", broken);
  const std::string flags = "--fov-y 40 --ao-radius 0.5 --world-to-camera \"" + std::string(kWorldToCamera) + "\" ";
  Outcome r = run("import-blender", flags + "--out " + (d / "ds") + " " + (d / "renders"));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find(d / "renders/b.exr"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "ds/a.exr"));
  EXPECT_FALSE(fs::exists(d / "ds"));
}
