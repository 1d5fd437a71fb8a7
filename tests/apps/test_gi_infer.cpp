// gi-infer, run as the user runs it, on frames of a tiny synthetic surround dataset and of
// a tiny rendered one (render-dataset), both with 32x32 faces (the models take 16x16:
// every run box-filters by 2, and by default brings the light back up to 32x32). Its
// light equals the prediction eval-gi's path computes for the same frame (load_samples +
// predict_linear, and with --upsample-from its upsampled_light, with the ground truth
// present), bit for bit; and it refuses what it must, naming the file and the problem,
// leaving no output behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "data/dataset.h"
#include "data/exr_io.h"
#include "models/gi/gi_model_io.h"
#include "models/gi/upsampled_light.h"
#include "report/image_write.h"
#include "runs/gi/gi_samples.h"
#include "runs/gi/model_light.h"
#include "tests/support/run_command.h"
#include "tests/support/synthetic_gi_dataset.h"

namespace fs = std::filesystem;
using nns::data::View;
using nns::testing::run_app;

namespace {

std::string read_all(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<std::string> files_in(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (auto& e : fs::directory_iterator(dir, ec)) out.push_back(e.path().filename().string());
  return out;
}

// A copy of a frame folder (or one view) without the ground truth: gi-infer's case.
void copy_without_truth(const std::string& from, const std::string& to) {
  auto strip = [](View v) {
    for (const char* c : {"indirect.R", "indirect.G", "indirect.B"}) v.channels.erase(c);
    return v;
  };
  if (fs::is_directory(from)) {
    fs::create_directories(to);
    for (auto& e : fs::directory_iterator(from))
      nns::data::write_view((fs::path(to) / e.path().filename()).string(),
                            strip(nns::data::read_view(e.path().string())));
  } else {
    nns::data::write_view(to, strip(nns::data::read_view(from)));
  }
}

class GiInfer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("nns_gi_infer_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    nns::testing::write_dataset(data(), 3, 2, false, /*face_size=*/32);
    // A path-traced dataset too (Embree, procedural rooms with an emission channel,
    // which the synthetic one lacks): 2 train frames and 1 held-out frame, cheap settings.
    auto rd =
        run_app("render-dataset", "--out " + rendered() +
                                      " --preset surround --views 3 --views-per-scene 1"
                                      " --test-fraction 0.34 --size 32x32 --spp 2 --gi-spp 4 --bounces 2 --seed 5");
    ASSERT_EQ(rd.code, 0) << rd.output;
    const std::pair<std::string, std::string> runs[] = {
        {"surround", data()}, {"front", data()}, {"rendered", rendered()}};
    for (auto& [name, dir] : runs) {
      const std::string mode = name == "front" ? "front" : "surround";
      auto r = run_app("train-gan", "--data " + dir + " --out " + (root_ / name).string() + " --mode " + mode +
                                        " --size 16 --ngf 4 --ndf 4 --levels 3 --d-layers 2 --epochs 2"
                                        " --no-eval --seed 3 --threads 2");
      ASSERT_EQ(r.code, 0) << r.output;
    }
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }

  static std::string data() { return (root_ / "data").string(); }
  static std::string rendered() { return (root_ / "rendered_data").string(); }
  static std::string model(const std::string& mode) { return (root_ / mode / "G.blob").string(); }
  static std::string path(const std::string& name) { return (root_ / name).string(); }

  // What eval-gi predicts for test item `index` (with its ground truth on disk): at the
  // model's face size, or with `upsampled` as `eval-gi --size 32 --upsample-from 16` does
  // (score_model: the prediction at 16, upsampled_light to the frame as stored);
  // `mirror_average` as --mirror-average.
  static nns::Tensor<float> eval_gi_prediction(const std::string& blob, size_t index, nns::gi::GiSample* out,
                                               const std::string& dataset = data(), bool upsampled = false,
                                               bool mirror_average = false) {
    using namespace nns::gi;
    using namespace nns::runs;
    LoadedGenerator g = load_generator(blob);
    auto listing = nns::data::list_dataset(dataset);
    GiItemReader rd{g.inputs.mode, g.inputs.size};
    auto samples = load_samples(listing.test, rd, g.inputs, index + 1, "test", /*quiet=*/true);
    *out = samples[index];
    nns::Tensor<float> light =
        model_light(g, samples[index], /*bn_batch_stats=*/true, /*dropout_on=*/false, mirror_average);
    if (!upsampled) return light;
    auto full = load_samples(listing.test, GiItemReader{g.inputs.mode, 0}, g.inputs, index + 1, "test", true);
    *out = full[index];
    return upsampled_light(light, samples[index], full[index]);
  }

  // Bitwise: gi-infer runs the same code on the same numbers (the EXR stores FLOAT).
  static void expect_output_matches(const std::string& exr, const nns::Tensor<float>& light,
                                    const nns::gi::GiSample& s) {
    View o = nns::data::read_view(exr);
    const int size = int(light.size(1));
    ASSERT_EQ(o.width, size);
    ASSERT_EQ(o.height, size);
    const int64_t n = int64_t(size) * size;
    double max_diff = 0, max_light_vs_direct = 0;
    for (int c = 0; c < 3; ++c) {
      const std::string ch(1, "RGB"[c]);
      const auto &L = o.channel("light." + ch), &I = o.channel("indirect." + ch), &S = o.channel("shaded." + ch);
      for (int64_t i = 0; i < n; ++i) {
        const int64_t k = c * n + i;
        max_diff = std::max(max_diff, double(std::abs(L[size_t(i)] - light[k])));
        EXPECT_EQ(I[size_t(i)], light[k] - s.direct_env[k]) << ch << " " << i;
        EXPECT_EQ(S[size_t(i)], s.albedo[k] * light[k] + s.emission[k]) << ch << " " << i;
        max_light_vs_direct = std::max(max_light_vs_direct, double(std::abs(light[k] - s.direct_env[k])));
      }
    }
    EXPECT_EQ(max_diff, 0.0) << "gi-infer's light differs from eval-gi's prediction";
    EXPECT_GT(max_light_vs_direct, 1e-3);  // the network added something: not an identity copy
    EXPECT_EQ(o.fov_y_deg, 90.0f);
    EXPECT_EQ(o.scene, s.scene);
    EXPECT_FALSE(s.scene.empty());
    EXPECT_TRUE(o.has("Z"));
    EXPECT_FALSE(o.has("direct.R"));  // the outputs only, no input planes copied
  }

  // Planes of `v` as one image file (report/image_write.h), channels named `names`.
  static std::string write_planes(const View& v, const std::string& file, std::vector<std::string> names,
                                  std::vector<std::string> planes,
                                  nns::report::PixelType type = nns::report::PixelType::f32) {
    const size_t n = size_t(v.width) * size_t(v.height), nc = names.size();
    std::vector<float> px(n * nc);
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < nc; ++c) px[i * nc + c] = v.channel(planes[c])[i];
    nns::report::write_image(file, v.width, v.height, names, px.data(), type);
    return file;
  }

  static inline fs::path root_;
};

}  // namespace

TEST_F(GiInfer, SurroundFrameWithoutTruthGivesEvalGisPrediction) {
  nns::gi::GiSample s;
  nns::Tensor<float> light = eval_gi_prediction(model("surround"), 1, &s, data(), /*upsampled=*/true);
  const std::string frame = path("bare_frame1");
  copy_without_truth(data() + "/test/frame1", frame);
  ASSERT_FALSE(nns::data::read_view(frame + "/front.exr").has("indirect.R"));
  fs::create_directories(path("out_s"));
  const std::string exr = path("out_s") + "/f1.exr";
  auto r = run_app("gi-infer", "--model " + model("surround") + " --in " + frame + " --out " + exr);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("32x32, box filter 2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("guided upsample back to 32x32"), std::string::npos) << r.output;
  expect_output_matches(exr, light, s);
  auto files = files_in(path("out_s"));
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"f1.exr", "f1_indirect.png", "f1_shaded.png"}));

  // --output-size model: the network's own 16x16, eval-gi's prediction without the upsample.
  nns::gi::GiSample s16;
  nns::Tensor<float> light16 = eval_gi_prediction(model("surround"), 1, &s16);
  auto rm = run_app("gi-infer", "--model " + model("surround") + " --in " + frame + " --out " + path("out_s16") +
                                    "/f1.exr --output-size model");
  ASSERT_EQ(rm.code, 0) << rm.output;
  EXPECT_EQ(rm.output.find("guided upsample"), std::string::npos) << rm.output;
  expect_output_matches(path("out_s16") + "/f1.exr", light16, s16);

  // --mirror-average: eval-gi's mirror-averaged light, upsampled the same way; not the plain light.
  nns::gi::GiSample sm;
  nns::Tensor<float> mirrored_light =
      eval_gi_prediction(model("surround"), 1, &sm, data(), /*upsampled=*/true, /*mirror_average=*/true);
  auto ra = run_app("gi-infer", "--model " + model("surround") + " --in " + frame + " --out " + path("out_sm") +
                                    "/f1.exr --mirror-average");
  ASSERT_EQ(ra.code, 0) << ra.output;
  expect_output_matches(path("out_sm") + "/f1.exr", mirrored_light, sm);
  EXPECT_NE(read_all(path("out_sm") + "/f1.exr"), read_all(exr));

  // One thread gives the same bytes (the determinism contract reaches the app).
  auto r1 = run_app("gi-infer", "--model " + model("surround") + " --in " + frame + " --out " + path("out_s") +
                                    "/t1.exr --threads 1");
  ASSERT_EQ(r1.code, 0) << r1.output;
  EXPECT_EQ(read_all(path("out_s") + "/t1.exr"), read_all(exr));
}

TEST_F(GiInfer, RenderedSurroundFrameGivesEvalGisPrediction) {
  auto listing = nns::data::list_dataset(rendered());
  ASSERT_EQ(listing.test.frames.size(), 1u);
  nns::gi::GiSample s;
  nns::Tensor<float> light = eval_gi_prediction(model("rendered"), 0, &s, rendered(), /*upsampled=*/true);
  const std::string frame = path("bare_rendered");
  copy_without_truth(listing.test.frames[0].dir, frame);
  const std::string exr = path("out_r") + "/r.exr";
  auto r = run_app("gi-infer", "--model " + model("rendered") + " --in " + frame + " --out " + exr);
  ASSERT_EQ(r.code, 0) << r.output;
  expect_output_matches(exr, light, s);
}

TEST_F(GiInfer, FrontModelOnASingleViewAndOnAFolder) {
  nns::gi::GiSample s;
  nns::Tensor<float> light = eval_gi_prediction(model("front"), 0, &s, data(), /*upsampled=*/true);
  const std::string view = path("bare_view0.exr");
  copy_without_truth(data() + "/test/frame0/front.exr", view);
  fs::create_directories(path("out_f"));
  auto r = run_app("gi-infer", "--model " + model("front") + " --in " + view + " --out " + path("out_f") + "/v.exr");
  ASSERT_EQ(r.code, 0) << r.output;
  expect_output_matches(path("out_f") + "/v.exr", light, s);

  // Given a folder, a front-mode model takes its front.exr and says so.
  const std::string frame = path("bare_frame0");
  copy_without_truth(data() + "/test/frame0", frame);
  auto rf = run_app("gi-infer", "--model " + model("front") + " --in " + frame + " --out " + path("out_f") + "/d.exr");
  ASSERT_EQ(rf.code, 0) << rf.output;
  EXPECT_NE(rf.output.find("using " + frame + "/front.exr"), std::string::npos) << rf.output;
  expect_output_matches(path("out_f") + "/d.exr", light, s);
}

// The same frame as the user's own float images (data/image_read.h, --channel): one EXR
// with its own channel names for depth and normals, a float TIFF for albedo, an EXR with
// other names for direct light, and emission and env where the view has them — the same
// light, bit for bit, as gi-infer on the view EXR. A surround model refuses --channel.
TEST_F(GiInfer, FrontModelOnTheFrameAsImagesGivesTheSameLight) {
  const std::string view = path("img_view0.exr");
  copy_without_truth(data() + "/test/frame0/front.exr", view);
  const View v = nns::data::read_view(view);
  auto write = [&](const std::string& name, std::vector<std::string> names, std::vector<std::string> planes) {
    return write_planes(v, path(name), names, planes);
  };
  const std::string g = write("img_gbuf.exr", {"depth.V", "nrm.x", "nrm.y", "nrm.z"}, {"Z", "N.X", "N.Y", "N.Z"});
  std::string flags = " --channel depth=" + g + ":depth.V --channel normal=" + g + ":nrm.x,nrm.y,nrm.z";
  flags += " --channel albedo=" + write("img_albedo.tif", {"R", "G", "B"}, {"albedo.R", "albedo.G", "albedo.B"});
  flags += " --channel direct=" + write("img_direct.exr", {"d.r", "d.g", "d.b"}, {"direct.R", "direct.G", "direct.B"}) +
           ":d.r,d.g,d.b";
  int optional = 0;
  for (const char* t : {"emission", "env"})
    if (v.has(std::string(t) + ".R")) {
      const std::string T(t);
      flags += " --channel " + T + "=" + write("img_" + T + ".tif", {"R", "G", "B"}, {T + ".R", T + ".G", T + ".B"});
      ++optional;
    }
  char fov[32];
  std::snprintf(fov, sizeof fov, " --fov-y %.9g", double(v.fov_y_deg));
  fs::create_directories(path("out_img"));
  auto ref =
      run_app("gi-infer", "--model " + model("front") + " --in " + view + " --out " + path("out_img") + "/ref.exr");
  ASSERT_EQ(ref.code, 0) << ref.output;
  auto r = run_app("gi-infer", "--model " + model("front") + flags + fov + " --out " + path("out_img") + "/img.exr");
  ASSERT_EQ(r.code, 0) << r.output;
  const View a = nns::data::read_view(path("out_img") + "/ref.exr"),
             b = nns::data::read_view(path("out_img") + "/img.exr");
  for (const char* c : {"light.R", "light.G", "light.B", "shaded.R", "shaded.G", "shaded.B", "Z"})
    EXPECT_EQ(a.channel(c), b.channel(c)) << c;
  EXPECT_TRUE(fs::exists(path("out_img") + "/img_shaded.png"));
  std::printf("gi-infer on the frame as float images (%d optional inputs): same light as on its EXR\n", optional);

  // Without --fov-y; with a surround model.
  auto no_fov = run_app("gi-infer", "--model " + model("front") + flags + " --out " + path("out_img") + "/nofov.exr");
  EXPECT_EQ(no_fov.code, 1) << no_fov.output;
  EXPECT_NE(no_fov.output.find("--fov-y is required"), std::string::npos) << no_fov.output;
  auto sur = run_app("gi-infer", "--model " + model("surround") + flags + fov + " --out " + path("out_img") + "/s.exr");
  EXPECT_EQ(sur.code, 1) << sur.output;
  EXPECT_NE(sur.output.find("--channel without faces gives one view"), std::string::npos) << sur.output;
  EXPECT_NE(sur.output.find("FACE.TARGET=FILE"), std::string::npos) << sur.output;
  EXPECT_FALSE(fs::exists(path("out_img") + "/nofov.exr"));
  EXPECT_FALSE(fs::exists(path("out_img") + "/s.exr"));
}

// Each refusal names the file and the problem, exits non-zero, and writes nothing: the
// output folder stays empty and an existing OUT.exr keeps its bytes.
TEST_F(GiInfer, RefusesBadInputNamingTheFileAndLeavesNoOutput) {
  const std::string frame = path("neg_frame");
  copy_without_truth(data() + "/test/frame0", frame);
  const std::string out_dir = path("out_neg");
  fs::create_directories(out_dir);
  const std::string out = out_dir + "/o.exr";
  auto expect_refused = [&](const std::string& args, const std::vector<std::string>& needles) {
    auto r = run_app("gi-infer", args + " --out " + out);
    EXPECT_NE(r.code, 0) << args << "\n" << r.output;
    for (auto& s : needles) EXPECT_NE(r.output.find(s), std::string::npos) << "'" << s << "' not in: " << r.output;
    EXPECT_TRUE(files_in(out_dir).empty()) << args;
  };

  // A missing channel, named with its file.
  const std::string no_direct = path("neg_frame_nodirect");
  copy_without_truth(frame, no_direct);
  {
    View v = nns::data::read_view(no_direct + "/right.exr");
    v.channels.erase("direct.G");
    nns::data::write_view(no_direct + "/right.exr", v);
  }
  expect_refused("--model " + model("surround") + " --in " + no_direct, {no_direct + "/right.exr", "'direct.G'"});

  // NaN in the front view.
  const std::string nan_view = path("neg_nan.exr");
  {
    View v = nns::data::read_view(frame + "/front.exr");
    v.channels["albedo.R"][37] = NAN;
    nns::data::write_view(nan_view, v);
  }
  expect_refused("--model " + model("front") + " --in " + nan_view, {nan_view, "albedo.R", "NaN"});

  // Wrong mode: a surround model needs a folder of six faces.
  expect_refused("--model " + model("surround") + " --in " + frame + "/front.exr",
                 {frame + "/front.exr", "surround model", "folder of six faces"});
  // A surround frame with a face missing.
  const std::string five = path("neg_five");
  copy_without_truth(frame, five);
  fs::remove(five + "/up.exr");
  expect_refused("--model " + model("surround") + " --in " + five, {five, "missing up.exr"});

  // Sizes an integer box filter cannot bring to 16: 24 (not a multiple) and 8 (smaller).
  for (int size : {24, 8}) {
    const std::string odd = path("neg_size" + std::to_string(size) + ".exr");
    nns::data::write_view(odd, nns::testing::make_face(size, 3, 0, false, 7));
    const std::string dims = std::to_string(size) + "x" + std::to_string(size);
    expect_refused("--model " + model("front") + " --in " + odd, {odd, dims, "16x16"});
  }

  // A model that is not one.
  const std::string junk = path("junk.blob");
  std::ofstream(junk) << "not a blob";
  expect_refused("--model " + junk + " --in " + frame, {junk});
  expect_refused("--model " + path("nonexistent.blob") + " --in " + frame, {path("nonexistent.blob")});

  // An existing output survives a failed run unchanged.
  std::ofstream(out) << "previous";
  auto r = run_app("gi-infer", "--model " + model("surround") + " --in " + no_direct + " --out " + out);
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(read_all(out), "previous");
  EXPECT_EQ(files_in(out_dir).size(), 1u);

  // Flags: an output that is not .exr; --help.
  auto bad_out =
      run_app("gi-infer", "--model " + model("front") + " --in " + nan_view + " --out " + out_dir + "/x.png");
  EXPECT_NE(bad_out.code, 0);
  EXPECT_NE(bad_out.output.find(".exr"), std::string::npos) << bad_out.output;
  auto help = run_app("gi-infer", "--help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.output.find("--model"), std::string::npos);
  EXPECT_NE(help.output.find("front/back/left/right/up/down.exr"), std::string::npos);
}

// A surround frame as the user's own images, six faces by --channel FACE.TARGET=FILE.
// `images(face, prefix)` writes one face's files and returns its flags.
namespace {

float srgb_encode_float(float x) {  // IEC 61966-2-1, the inverse of image_read's decode
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1 / 2.4f) - 0.055f;
}

// One face's files: depth and normals in one EXR with its own channel names, albedo a
// float TIFF, direct an EXR with other names, env a TIFF (where the face has it); with
// `png16`, normals and albedo as 16-bit PNGs instead (normal (n+1)/2, albedo sRGB).
std::string face_flags(const View& v, const std::string& face, const std::string& dir, bool png16,
                       const std::function<std::string(const View&, const std::string&, std::vector<std::string>,
                                                       std::vector<std::string>, nns::report::PixelType)>& write) {
  using nns::report::PixelType;
  const std::string p = dir + "/" + face;
  std::string f;
  if (png16) {
    f += " --channel " + face + ".depth=" + write(v, p + "_z.exr", {"depth.V"}, {"Z"}, PixelType::f32);
    View enc = v;
    for (const char* c : {"N.X", "N.Y", "N.Z"})
      for (auto& x : enc.channels[c]) x = (x + 1) / 2;
    for (const char* c : {"albedo.R", "albedo.G", "albedo.B"})
      for (auto& x : enc.channels[c]) x = srgb_encode_float(x);
    f += " --channel " + face +
         ".normal=" + write(enc, p + "_n.png", {"R", "G", "B"}, {"N.X", "N.Y", "N.Z"}, PixelType::u16);
    f += " --channel " + face +
         ".albedo=" + write(enc, p + "_a.png", {"R", "G", "B"}, {"albedo.R", "albedo.G", "albedo.B"}, PixelType::u16);
  } else {
    const std::string g =
        write(v, p + "_gbuf.exr", {"depth.V", "nrm.x", "nrm.y", "nrm.z"}, {"Z", "N.X", "N.Y", "N.Z"}, PixelType::f32);
    f += " --channel " + face + ".depth=" + g + ":depth.V --channel " + face + ".normal=" + g + ":nrm.x,nrm.y,nrm.z";
    f += " --channel " + face + ".albedo=" +
         write(v, p + "_albedo.tif", {"R", "G", "B"}, {"albedo.R", "albedo.G", "albedo.B"}, PixelType::f32);
  }
  f += " --channel " + face + ".direct=" +
       write(v, p + "_direct.exr", {"d.r", "d.g", "d.b"}, {"direct.R", "direct.G", "direct.B"}, PixelType::f32) +
       ":d.r,d.g,d.b";
  for (const char* t : {"emission", "env"})
    if (v.has(std::string(t) + ".R")) {
      const std::string T(t);
      f += " --channel " + face + "." + T + "=" +
           write(v, p + "_" + T + ".tif", {"R", "G", "B"}, {T + ".R", T + ".G", T + ".B"}, PixelType::f32);
    }
  return f;
}

}  // namespace

TEST_F(GiInfer, SurroundModelOnTheFrameAsImages) {
  const std::string frame = path("img_sframe1");
  copy_without_truth(data() + "/test/frame1", frame);
  const std::string dir = path("img_s"), out = path("out_simg");
  fs::create_directories(dir);
  fs::create_directories(dir + "16");
  fs::create_directories(out);
  const auto write = &GiInfer::write_planes;
  std::string flags, flags16;
  std::array<View, 6> faces;
  for (size_t f = 0; f < 6; ++f) {
    const std::string face = nns::data::kFaceNames[f];
    faces[f] = nns::data::read_view(frame + "/" + face + ".exr");
    flags += face_flags(faces[f], face, dir, false, write);
    flags16 += face_flags(faces[f], face, dir + "16", true, write);
  }
  auto ref = run_app("gi-infer", "--model " + model("surround") + " --in " + frame + " --out " + out + "/ref.exr");
  ASSERT_EQ(ref.code, 0) << ref.output;
  const View a = nns::data::read_view(out + "/ref.exr");

  // Float EXR and TIFF faces: the folder's prediction, bit for bit (with and without --fov-y 90).
  for (const char* fov : {"", " --fov-y 90"}) {
    auto r = run_app("gi-infer", "--model " + model("surround") + flags + fov + " --out " + out + "/img.exr");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("surround model, front face ("), std::string::npos) << r.output;
    const View b = nns::data::read_view(out + "/img.exr");
    for (const char* c : {"light.R", "light.G", "light.B", "shaded.R", "shaded.G", "shaded.B", "Z"})
      EXPECT_EQ(a.channel(c), b.channel(c)) << c << fov;
    EXPECT_EQ(b.fov_y_deg, 90.0f);
  }

  // 16-bit PNG normals and albedo: rounded to the nearest of 65536 codes, so a normal
  // component moves by at most 1/65535 (then renormalised) and an albedo by at most
  // 0.5/65535 times the sRGB decode's largest slope (2.28), 1.8e-5. Measured over the
  // 16x16 front: the light moved by at most 3.6e-6, the lit image (albedo * light, its
  // error about 1.8e-5 * light) by 2.5e-5; the bounds are 10x those. A wrong decode
  // (albedo not sRGB-decoded, normals not remapped) moves them by 1e-1 or so.
  auto r16 = run_app("gi-infer", "--model " + model("surround") + flags16 + " --out " + out + "/png16.exr");
  ASSERT_EQ(r16.code, 0) << r16.output;
  const View c = nns::data::read_view(out + "/png16.exr");
  double light_diff = 0, shaded_diff = 0;
  for (const char* ch : {"R", "G", "B"})
    for (size_t i = 0; i < a.channel("Z").size(); ++i) {
      light_diff = std::max(light_diff, double(std::abs(a.channel(std::string("light.") + ch)[i] -
                                                        c.channel(std::string("light.") + ch)[i])));
      shaded_diff = std::max(shaded_diff, double(std::abs(a.channel(std::string("shaded.") + ch)[i] -
                                                          c.channel(std::string("shaded.") + ch)[i])));
    }
  std::printf(
      "gi-infer, surround frame with 16-bit PNG normals and albedo: max |light diff| %.3g, "
      "max |shaded diff| %.3g\n",
      light_diff, shaded_diff);
  EXPECT_LT(light_diff, 3.6e-5);
  EXPECT_LT(shaded_diff, 2.5e-4);
  EXPECT_EQ(a.channel("Z"), c.channel("Z"));
}

// Every refusal of --channel for a surround frame: non-zero exit, a message naming the
// problem (and the face or file), and no output.
TEST_F(GiInfer, SurroundImagesRefusalsNameTheProblemAndWriteNothing) {
  const std::string frame = path("img_rframe0");
  copy_without_truth(data() + "/test/frame0", frame);
  const std::string dir = path("img_r"), out_dir = path("out_rimg"), out = out_dir + "/o.exr";
  fs::create_directories(dir);
  fs::create_directories(out_dir);
  const auto write = &GiInfer::write_planes;
  std::array<std::string, 6> face;  // each face's flags
  std::string all;
  for (size_t f = 0; f < 6; ++f) {
    const std::string name = nns::data::kFaceNames[f];
    face[f] = face_flags(nns::data::read_view(frame + "/" + name + ".exr"), name, dir, false, write);
    all += face[f];
  }
  auto expect_refused = [&](const std::string& model_name, const std::string& flags,
                            const std::vector<std::string>& needles) {
    auto r = run_app("gi-infer", "--model " + model(model_name) + flags + " --out " + out);
    EXPECT_NE(r.code, 0) << flags << "\n" << r.output;
    for (auto& s : needles) EXPECT_NE(r.output.find(s), std::string::npos) << "'" << s << "' not in: " << r.output;
    EXPECT_TRUE(files_in(out_dir).empty()) << r.output;
  };
  auto without = [](std::string flags, const std::string& target) {  // drops " --channel TARGET=..."
    const auto at = flags.find(" --channel " + target + "=");
    return flags.erase(at, flags.find(" --channel", at + 1) - at);
  };
  // Missing faces and targets, all in one message.
  expect_refused("surround",
                 face[0] + without(face[1], "back.depth") + face[2] + face[3] + without(face[4], "up.normal"),
                 {"missing: back.depth, up.normal, down (all of depth, normal, albedo, direct)"});
  expect_refused("surround", all + " --channel sideways.depth=" + dir + "/front_gbuf.exr:depth.V",
                 {"sideways.depth", "unknown face 'sideways'", "front, back, left, right, up, down"});
  expect_refused("surround", all + " --channel front.colour=" + dir + "/front_albedo.tif",
                 {"front.colour", "unknown target 'colour'"});
  expect_refused("surround", all + " --channel depth=" + dir + "/front_gbuf.exr:depth.V",
                 {"'depth=" + dir + "/front_gbuf.exr:depth.V' names no face", "FACE.TARGET=FILE"});
  expect_refused("front", all + " --fov-y 90", {"--channel 'front.depth=", "front-mode model", "without a face"});
  expect_refused("surround", all + " --fov-y 60", {"--fov-y 60", "90-degree", "--fov-y 90 or leave it out"});
  // A face of another size, named with its files.
  {
    View small = nns::testing::make_face(16, 0, 2, false, 9);
    fs::create_directories(dir + "/small");
    std::string flags =
        face[0] + face[1] + face_flags(small, "left", dir + "/small", false, write) + face[3] + face[4] + face[5];
    expect_refused("surround", flags, {"left face (", dir + "/small/left_", "16x16 but front is 32x32"});
  }
  // A hint names the face-prefixed target to copy.
  expect_refused("surround", without(all, "back.normal") + " --channel back.normal=" + dir + "/back_gbuf.exr",
                 {dir + "/back_gbuf.exr", "has 4 channels", "--channel back.normal=" + dir + "/back_gbuf.exr:"});
}

// What a gi-infer killed mid-write leaves ("<name>.tmp.<pid>" of a process that is gone)
// is removed by the next run into the same names, and nothing else in the user's folder
// is touched.
TEST_F(GiInfer, TheNextRunRemovesAKilledRunsTemporaries) {
  const std::string frame = path("stale_frame1");
  copy_without_truth(data() + "/test/frame1", frame);
  fs::create_directories(path("out_stale"));
  const std::string exr = path("out_stale") + "/f1.exr";
  // A pid that is no process: beyond the kernel's pid_max (at most 2^22).
  const std::string dead = ".tmp.99999999";
  for (const std::string& f : {exr, path("out_stale") + "/f1_shaded.png", path("out_stale") + "/f1_indirect.png",
                               path("out_stale") + "/other.exr"})
    std::ofstream(f + dead) << "torn";
  auto r = run_app("gi-infer", "--model " + model("surround") + " --in " + frame + " --out " + exr);
  ASSERT_EQ(r.code, 0) << r.output;
  auto files = files_in(path("out_stale"));
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"f1.exr", "f1_indirect.png", "f1_shaded.png", "other.exr" + dead}));
}
