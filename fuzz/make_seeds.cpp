// Writes the seed corpus of every fuzz target with the project's own writers:
//   make_seeds DIR   ->  DIR/blob, DIR/checkpoint, DIR/exr, DIR/scene, DIR/metrics
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "classical_ao/params.h"
#include "core/atomic_file.h"
#include "core/blob.h"
#include "data/exr_io.h"
#include "nn/linear.h"
#include "optim/adam.h"
#include "optim/checkpoint.h"
#include "report/image_write.h"

using namespace nns;
namespace fs = std::filesystem;

namespace {
void put(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
}

data::View view(int w, int h) {
  data::View v;
  v.width = w, v.height = h;
  v.fov_y_deg = 60, v.ao_radius = 0.5f, v.scene = "seed";
  v.world_to_camera = std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -2, 0, 0, 0, 1};
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z", "AO", "albedo.R", "direct.R", "indirect.R"}) v.add_channel(c);
  for (int i = 0; i < w * h; ++i) {
    v.channels["Z"][size_t(i)] = 1 + 0.01f * float(i);
    v.channels["N.Z"][size_t(i)] = 1;
    v.channels["AO"][size_t(i)] = float(i % 5) / 5;
    v.channels["albedo.R"][size_t(i)] = 0.5f;
    v.channels["direct.R"][size_t(i)] = float(i % 3);
  }
  v.channels["Z"][0] = INFINITY;
  return v;
}

// Compressions and layouts write_view does not produce, through OpenEXR directly.
void raw_exr(const fs::path& p, Imf::Compression c, bool tiled, Imf::PixelType type) {
  const int w = 8, h = 8;
  Imf::Header hd(w, h);
  hd.compression() = c;
  hd.channels().insert("Z", Imf::Channel(Imf::FLOAT));
  hd.channels().insert("AO", Imf::Channel(type));
  std::vector<float> z(size_t(w * h), 2.0f), ao(size_t(w * h), 0.25f);
  std::vector<half> ao_h(ao.begin(), ao.end());
  Imf::FrameBuffer fb;
  fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(z.data()), 4, 4 * w));
  if (type == Imf::HALF) fb.insert("AO", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(ao_h.data()), 2, 2 * w));
  else fb.insert("AO", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(ao.data()), 4, 4 * w));
  fs::create_directories(p.parent_path());
  if (tiled) {
    hd.setTileDescription(Imf::TileDescription(4, 4, Imf::ONE_LEVEL));
    Imf::TiledOutputFile out(p.c_str(), hd);
    out.setFrameBuffer(fb);
    out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
  } else {
    Imf::OutputFile out(p.c_str(), hd);
    out.setFrameBuffer(fb);
    out.writePixels(h);
  }
}

// A render as tools/blender_capture.py leaves it: Blender's pass names and the capture
// note in the header's "Note" (data/blender_capture_note.h), for import-blender's path.
void blender_exr(const fs::path& p) {
  const int w = 4, h = 4;
  Imf::Header hd(w, h);
  hd.insert("Note", Imf::StringAttribute("nnshade-camera 1\nfovY=40\nworldToCamera=1,0,0,0,0,0,1,-1,0,-1,0,2,0,0,0,1\n"
                                         "aoRadius=1\nscene=room\ncamera=Front"));
  std::vector<float> plane(size_t(w * h), 0.5f);
  Imf::FrameBuffer fb;
  for (const char* c : {"ViewLayer.Depth.Z", "ViewLayer.Normal.X", "ViewLayer.Normal.Y", "ViewLayer.Normal.Z",
                        "ViewLayer.AO.R", "ViewLayer.AO.G", "ViewLayer.AO.B"}) {
    hd.channels().insert(c, Imf::Channel(Imf::FLOAT));
    fb.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(plane.data()), 4, 4 * w));
  }
  fs::create_directories(p.parent_path());
  Imf::OutputFile out(p.c_str(), hd);
  out.setFrameBuffer(fb);
  out.writePixels(h);
}

// blob: a small weights file like save_weights writes.
void blob_seeds(const fs::path& dir) {
  Blob w("nnao");
  w.set_config("hidden", 4), w.set_config("lr", 1e-3), w.set_config("activation", "prelu");
  w.put("fc.weight", Tensor<float>::from({2, 3}, {1, -2, 3.5f, 0, 1e-30f, -0.0f}));
  w.put("fc.bias", Tensor<double>::from({2}, {0.1, -0.2}));
  w.put_i64("step", 3);
  put(dir / "blob" / "weights.blob", w.serialize());
  put(dir / "blob" / "empty.blob", Blob("x").serialize());
}

// checkpoint: what the fuzz target restores into, saved by Checkpoint itself.
void checkpoint_seeds(const fs::path& dir, Rng& rng) {
  Linear<float> net(rng, 3, 2);
  Adam<float> opt(net.parameters());
  Rng data_rng(2);
  int64_t epoch = 4, step = 40;
  Checkpoint<float> ck;
  ck.add_module("net", net)
      .add_optimizer("adam", opt)
      .add_rng("data", data_rng)
      .add_counter("epoch", epoch)
      .add_counter("step", step);
  Blob meta("nnao-checkpoint");
  meta.set_config("lr", 1e-3);
  ck.fill(meta);
  put(dir / "checkpoint" / "run.ckpt", meta.serialize());
}

// exr: the project's writer (FLOAT and HALF), then other layouts OpenEXR reads.
void exr_seeds(const fs::path& dir) {
  fs::create_directories(dir / "exr");
  data::write_view((dir / "exr" / "float.exr").string(), view(6, 4));
  data::write_view((dir / "exr" / "half.exr").string(), view(5, 3), {.half = true});
  raw_exr(dir / "exr" / "piz_tiled.exr", Imf::PIZ_COMPRESSION, true, Imf::HALF);
  raw_exr(dir / "exr" / "rle.exr", Imf::RLE_COMPRESSION, false, Imf::FLOAT);
  raw_exr(dir / "exr" / "none.exr", Imf::NO_COMPRESSION, false, Imf::HALF);
  raw_exr(dir / "exr" / "pxr24.exr", Imf::PXR24_COMPRESSION, false, Imf::FLOAT);
  raw_exr(dir / "exr" / "b44.exr", Imf::B44_COMPRESSION, false, Imf::HALF);
  raw_exr(dir / "exr" / "dwaa.exr", Imf::DWAA_COMPRESSION, false, Imf::HALF);
  blender_exr(dir / "exr" / "blender.exr");
}

// scene: first byte 0 = OBJ, 1 = glTF, 2 = GLB (fuzz_scene.cpp).
void scene_seeds(const fs::path& dir) {
  put(dir / "scene" / "quad.obj", std::string(1, '\0') +
                                      "v -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nv 0 1 0\nvn 0 1 0\nvt 0 0\n"
                                      "o q\ng quad\nusemtl none\nf 1 2 3 4\nf 1/1/1 2/1/1 5/1/1\nf -1 -2 -3\n");
  put(dir / "scene" / "tri.gltf",
      std::string(1, '\1') +
          R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
          R"("nodes":[{"mesh":0,"translation":[0,2,0],"children":[1]},{"mesh":0,"scale":[2,2,2],"rotation":[0,0,0,1]}],)"
          R"("materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.4,0.6,1]},"emissiveFactor":[1,0,0]}],)"
          R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],)"
          R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]},)"
          R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],)"
          R"("bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],)"
          R"("buffers":[{"byteLength":42,"uri":"data:application/octet-stream;base64,)"
          R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAAAAAAIA/AAABAAIA"}]})");
}

// metrics: two little-endian bytes of the checkpoint's step, then the file the run
// layer writes (runs/metrics_log.h), with a null and a torn last line.
void metrics_seeds(const fs::path& dir) {
  put(dir / "metrics" / "three.jsonl", std::string("\x14\x00", 2) +
                                           "{\"step\":10,\"epoch\":1,\"train_loss\":0.5,\"test_mse\":0.25}\n"
                                           "{\"step\":20,\"epoch\":2,\"train_loss\":0.125,\"test_mse\":null}\n"
                                           "{\"step\":30,\"epoch\":3,\"train_loss\":0.001,\"test_m");
}

// image: first byte 0 = PNG, 1 = TIFF, 2 = HDR, 3 = EXR (fuzz_image.cpp), the file by
// the one image writer: what --channel reads, in each type the formats store.
void image_seeds(const fs::path& dir) {
  auto image = [&](const std::string& name, char format, std::vector<std::string> channels, report::PixelType t) {
    const std::string tmp = (dir / ("seed_tmp_" + name)).string();
    std::vector<float> px(size_t(6 * 4) * channels.size());
    for (size_t i = 0; i < px.size(); ++i) px[i] = 0.05f + 0.9f * float((i * 37) % 23) / 22.0f;
    report::write_image(tmp, 6, 4, channels, px.data(), t);
    put(dir / "image" / name, std::string(1, format) + read_file(tmp));
    fs::remove(tmp);
  };
  image("rgb8.png", 0, {"R", "G", "B"}, report::PixelType::u8);
  image("grey16.png", 0, {"Y"}, report::PixelType::u16);
  image("rgba8.png", 0, {"R", "G", "B", "A"}, report::PixelType::u8);
  image("float.tif", 1, {"R", "G", "B"}, report::PixelType::f32);
  image("grey16.tif", 1, {"Y"}, report::PixelType::u16);
  image("light.hdr", 2, {"R", "G", "B"}, report::PixelType::f32);
  image("names.exr", 3, {"depth.V", "nrm.x", "nrm.y", "nrm.z"}, report::PixelType::f32);
  image("half.exr", 3, {"Z"}, report::PixelType::f16);
}

// classical_params: the file tune-classical-ao writes (classical_ao/params.h).
void classical_params_seeds(const fs::path& dir) {
  classical_ao::ClassicalParams p;
  p.hbao.angle_bias = 0.2f, p.gtao.falloff = 0.5f;
  put(dir / "classical_params" / "tuned.txt", classical_ao::format_classical_params(p, "seed") + "# a comment\n\n");
}

// blender_import: width 2, height 1, a capture note as tools/blender_capture.py writes
// it, then the planes Depth.Z, Normal.X, Normal.Y, Normal.Z, AO.R (fuzz_blender_import.cpp).
void blender_import_seeds(const fs::path& dir) {
  std::string b =
      std::string("\x01\x00", 2) +
      "nnshade-camera 1\nfovY=40\nworldToCamera=1,0,0,5,0,0,1,-2,0,-1,0,7,0,0,0,1\naoRadius=0.75\nscene=room";
  b += '\0';
  for (float f : {3.0f, 1e10f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.5f, 0.0f})
    b.append(reinterpret_cast<const char*>(&f), 4);
  put(dir / "blender_import" / "two-pixels", b);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds DIR\n");
    return 2;
  }
  const fs::path dir = argv[1];
  Rng rng(7);
  blob_seeds(dir);
  checkpoint_seeds(dir, rng);
  exr_seeds(dir);
  scene_seeds(dir);
  metrics_seeds(dir);
  image_seeds(dir);
  classical_params_seeds(dir);
  blender_import_seeds(dir);
  std::printf("make_seeds: wrote %s/{blob,checkpoint,exr,scene,metrics,image,classical_params,blender_import}\n",
              dir.c_str());
  return 0;
}
