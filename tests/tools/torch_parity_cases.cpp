// The C++ side of the PyTorch parity test (tests/tools/test_nnshade_torch.py): random
// small models saved as the project's blobs, their inputs, and what the C++ forward
// computes from the blob it just wrote (loaded back, as eval-gi and nnao-infer do).
//
//   usage: torch_parity_cases DIR
//   DIR/<case>.blob         the model: kind nnao, pix2pix-unet or patchgan
//   DIR/<case>.cases.blob   kind "torch-parity-cases": inputs and C++ outputs
//
// Weights are redrawn at unit scale (pix2pix's N(0, 0.02) start would leave every
// output near 0, where a wrong layer could hide), and BatchNorm's running statistics are
// made non-trivial, so each test mode is checked on numbers that depend on it.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/blob.h"
#include "core/rng.h"
#include "fixtures/random_nnao_blob.h"
#include "fixtures/synthetic_gbuffer.h"
#include "models/gi/gi_model_io.h"
#include "models/nnao/nnao_exact_per_pixel.h"
#include "models/nnao/nnao_inference_reference.h"
#include "screen_space/gbuffer.h"

using namespace nns;

namespace {

std::string g_dir;

std::string path(const std::string& name) { return g_dir + "/" + name; }

void randomise(Module<float>& m, Rng& rng) {
  for (auto& [name, p] : m.named_parameters()) {
    Tensor<float>& v = p.value();
    const bool weight = name.size() >= 6 && name.compare(name.size() - 6, 6, "weight") == 0;
    const double sd = v.dim() >= 2 ? 1.0 / std::sqrt(double(v.numel() / v.size(0))) : 0.3;
    for (auto& x : v) x = float(rng.normal(weight && v.dim() == 1 ? 1.0 : 0.0, sd));
  }
  for (auto& [name, b] : m.named_buffers()) {
    const bool var = name.find("running_var") != std::string::npos;
    for (auto& x : *b) x = float(var ? rng.uniform(0.5, 2.0) : rng.normal(0.0, 0.3));
  }
}

Tensor<float> random_input(Rng& rng, int channels, int h, int w) {
  Tensor<float> x({1, channels, h, w});
  for (auto& v : x) v = float(rng.uniform(-1.0, 1.0));
  return x;
}

// NNAO: the raw inputs of every non-sky pixel of a synthetic view, the exact per-pixel
// inference there (nnao_exact_per_pixel.h) and the bilateral blur of its image; the
// view's depth and normals for the torch feature extraction.
void nnao_case(const std::string& name, Blob model) {
  model.save(path(name + ".blob"));
  const nnao::NnaoWeights m = nnao::NnaoWeights::load(path(name + ".blob"));
  // radius 0.7, not 1: with 1, the floor one unit below the camera puts grid samples
  // exactly on pixel edges (r kx is then a half-integer on every floor row).
  const data::View v = fixtures::synthetic_view(40, 24, 1, /*spp=*/1, /*radius=*/0.7f);
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(v);
  std::vector<float> ao_image(size_t(g.pixels()));
  nnao::infer_exact_per_pixel(m, g, ao_image.data());
  const int64_t F = m.features();
  std::vector<float> features, ao;
  std::vector<int64_t> pixels;
  std::vector<float> f(static_cast<size_t>(F));
  for (int64_t i = 0; i < g.pixels(); ++i) {
    if (g.sky(i)) continue;
    m.input.compute(g, int(i % g.width), int(i / g.width), f.data());
    features.insert(features.end(), f.begin(), f.end());
    ao.push_back(ao_image[size_t(i)]);
    pixels.push_back(i);
  }
  const int64_t n = int64_t(pixels.size());
  Blob c("torch-parity-cases");
  c.set_config("width", g.width);
  c.set_config("height", g.height);
  c.set_config("fov_y_deg", double(v.fov_y_deg));
  c.set_config("radius", double(g.radius));
  c.put("features", Shape{n, F}, features.data());
  c.put("ao", Shape{n}, ao.data());
  c.put("pixels", Shape{n}, pixels.data());
  c.put("depth", Shape{g.height, g.width}, g.z);
  std::vector<float> normal;
  for (const float* plane : {g.nx, g.ny, g.nz}) normal.insert(normal.end(), plane, plane + g.pixels());
  c.put("normal", Shape{3, g.height, g.width}, normal.data());
  c.put("ao_image", Shape{g.height, g.width}, ao_image.data());
  std::vector<float> blurred(ao_image.size());  // what a horizon model's exact inference ends with
  nnao::bilateral_blur_reference(g, ao_image.data(), blurred.data());
  c.put("ao_blurred", Shape{g.height, g.width}, blurred.data());
  // With the default model's edge terms (blur_depth 0.3, blur_normal_power 2).
  nnao::bilateral_blur_reference(g, ao_image.data(), blurred.data(), nnao::BlurEdges{0.3f, 2});
  c.put("ao_blurred_loose", Shape{g.height, g.width}, blurred.data());
  c.save(path(name + ".cases.blob"));
}

struct GCase {
  std::string name;
  gi::GeneratorConfig gc;
  gi::GiInputConfig in;
  int h, w;
};

// A generator: Tanh-range outputs in both BatchNorm modes (dropout off), and the
// linear light predict_linear gives (batch statistics), as eval-gi and gi-infer do.
void generator_case(GCase c, uint64_t seed) {
  Rng rng(seed);
  c.gc.unet.in_channels = c.in.channels();
  c.gc.hdr_scale = c.in.norm.hdr_scale;
  auto G = gi::make_generator<float>(c.gc, rng);
  randomise(*G, rng);
  gi::save_generator_blob(path(c.name + ".blob"), *G, c.in, c.gc, "gan");
  gi::LoadedGenerator L = gi::load_generator(path(c.name + ".blob"));
  gi::GiSample s;
  s.input = random_input(rng, c.in.channels(), c.h, c.w);
  s.front = {0, 0, c.w, c.h};
  NoGradGuard ng;
  Blob out("torch-parity-cases");
  out.put("input", s.input);
  // Running statistics first: a batch-statistics forward moves them (training mode).
  L.G->set_test_modes(/*bn_batch_stats=*/false, /*dropout_on=*/false);
  out.put("tanh_running", gi::generate(*L.G, L.config, Var<float>(s.input)).value());
  L.G->set_test_modes(true, false);
  out.put("tanh_batch", gi::generate(*L.G, L.config, Var<float>(s.input)).value());
  out.put("linear_batch", gi::predict_linear(L, s, true, false));
  out.save(path(c.name + ".cases.blob"));
}

void discriminator_case(const std::string& name, gi::PatchGanConfig pc, int h, int w, uint64_t seed) {
  Rng rng(seed);
  gi::PatchGan<float> d(pc, rng);
  randomise(d, rng);
  gi::save_discriminator_blob(path(name + ".blob"), d);
  auto D = gi::load_discriminator(path(name + ".blob"));
  const Tensor<float> x = random_input(rng, pc.in_channels, h, w);
  NoGradGuard ng;
  Blob out("torch-parity-cases");
  out.put("input", x);
  D->eval();
  out.put("logits_running", D->forward(Var<float>(x)).value());
  D->train();  // how training runs it: batch statistics
  out.put("logits_batch", D->forward(Var<float>(x)).value());
  out.save(path(name + ".cases.blob"));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: torch_parity_cases DIR\n");
    return 2;
  }
  g_dir = argv[1];
  try {
    using fixtures::random_nnao_blob, fixtures::spread_nnao_outputs;
    nnao_case("nnao-grid", spread_nnao_outputs(random_nnao_blob(/*window=*/5, /*hidden=*/6, 11), 20, 0.5f));
    const fixtures::HorizonShape horizon{/*directions=*/8, /*steps=*/4, /*bands=*/2};
    Blob h = spread_nnao_outputs(random_nnao_blob(0, 8, 12, false, horizon), 20, -0.3f);
    h.set_config("radius_term_max", 0.35);  // the default's kind of ceiling, low enough to hold some pixels
    nnao_case("nnao-horizon", h);

    gi::GiInputConfig front;  // 12 channels (CoordConv), HDR scale and light cap set
    front.mode = gi::GiMode::front;
    front.norm = {/*depth_max=*/10.0f, /*hdr_scale=*/0.6f, /*light_max=*/3.0f};
    gi::GiInputConfig plain = front;
    plain.coordconv = false;  // 10 channels
    plain.norm.light_max = INFINITY;
    gi::GeneratorConfig p2p;
    p2p.unet.ngf = 4, p2p.unet.levels = 3;
    gi::GeneratorConfig mapped = p2p, linear = p2p, nobn = p2p, deep = p2p, level = p2p, energy = p2p;
    mapped.residual = gi::GiResidual::mapped, mapped.unet.levels = 4;
    linear.residual = gi::GiResidual::linear;
    nobn.unet.batchnorm = false;
    level.residual = gi::GiResidual::linear, level.unet.level_head = 5;
    energy.residual = gi::GiResidual::linear, energy.unet.level_head = 4, energy.unet.level_energy = true;
    deep.arch = gi::GiArch::deepshading, deep.residual = gi::GiResidual::linear, deep.unet.levels = 2;
    generator_case({"G-pix2pix", p2p, front, 16, 16}, 21);
    generator_case({"G-pix2pix-mapped", mapped, plain, 16, 32}, 22);
    generator_case({"G-pix2pix-linear", linear, front, 24, 16}, 23);
    generator_case({"G-pix2pix-nobn", nobn, plain, 16, 16}, 24);
    generator_case({"G-deepshading", deep, front, 16, 24}, 25);
    generator_case({"G-pix2pix-level", level, front, 16, 16}, 26);
    generator_case({"G-pix2pix-level-energy", energy, front, 16, 16}, 27);

    discriminator_case("D-patchgan", {/*in_channels=*/15, /*ndf=*/4, /*layers=*/3}, 32, 32, 31);
    discriminator_case("D-patchgan-1layer", {13, 4, 1}, 16, 24, 32);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "torch_parity_cases: %s\n", e.what());
    return 1;
  }
  return 0;
}
