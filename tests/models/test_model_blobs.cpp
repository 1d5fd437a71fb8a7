// The model readers take a CRC-valid blob as outside bytes: a non-finite weight or
// statistic, a real-valued key that is no finite float, an integer key out of range as
// stored, each is refused naming the file and the tensor or key.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/blob.h"
#include "fixtures/random_nnao_blob.h"
#include "models/gi/gi_model_io.h"
#include "models/nnao/nnao_weights.h"

using namespace nns;
namespace fs = std::filesystem;

namespace {

class ModelBlobTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nns_model_blobs_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// `b` with value `i` of the f32 tensor `name` set to `v`.
Blob with_value(const Blob& b, const std::string& name, size_t i, float v) {
  Blob out(b.kind());
  for (auto& [k, val] : b.config()) out.set_config(k, val);
  bool found = false;
  for (auto& [n, t] : b.tensors()) {
    const Shape sh(t.dims.begin(), t.dims.end());
    if (t.dtype == DType::F32) {
      std::vector<float> x(size_t(t.numel()));
      std::memcpy(x.data(), t.bytes.data(), t.bytes.size());
      if (n == name) x.at(i) = v, found = true;
      out.put(n, sh, x.data());
    } else if (t.dtype == DType::F64) {
      out.put(n, sh, reinterpret_cast<const double*>(t.bytes.data()));
    } else if (t.dtype == DType::U64) {
      out.put(n, sh, reinterpret_cast<const uint64_t*>(t.bytes.data()));
    } else {
      out.put(n, sh, reinterpret_cast<const int64_t*>(t.bytes.data()));
    }
  }
  EXPECT_TRUE(found) << name;
  return out;
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

void expect_refused(const std::string& e, const std::string& file, const std::string& what) {
  EXPECT_NE(e.find(file), std::string::npos) << "the file is named: " << e;
  EXPECT_NE(e.find(what), std::string::npos) << "'" << what << "' is named: " << e;
}

// A NaN or inf weight gave AO = 0 (or 1) on every pixel with exit 0, and NaN/inf
// literals in the exported shader.
TEST_F(ModelBlobTest, NnaoRefusesANonFiniteWeightOrStatisticNamingTheTensor) {
  const Blob good = fixtures::random_nnao_blob(3, 4, 1);
  good.save(path("good.blob"));
  ASSERT_NO_THROW(nnao::NnaoWeights::load(path("good.blob")));
  for (const char* tensor :
       {"fc0.weight", "fc2.weight", "fc3.bias", "act1.alpha", "feature_mean", "feature_std", "target_stats"})
    for (float bad : {std::nanf(""), HUGE_VALF, -HUGE_VALF}) {
      const std::string p = path("bad.blob");
      with_value(good, tensor, 1 % (std::string(tensor) == "fc3.bias" ? 1 : 2), bad).save(p);
      expect_refused(error_of([&] { nnao::NnaoWeights::load(p); }), p, std::string("tensor '") + tensor + "'");
    }
}

// A zero feature_std or target std divides the weights into infinities.
TEST_F(ModelBlobTest, NnaoRefusesAStandardDeviationThatIsNotPositive) {
  const Blob good = fixtures::random_nnao_blob(3, 4, 2);
  for (auto [tensor, i] : {std::pair<const char*, size_t>{"feature_std", 5}, {"target_stats", 1}})
    for (float bad : {0.f, -0.5f}) {
      const std::string p = path("bad.blob");
      with_value(good, tensor, i, bad).save(p);
      expect_refused(error_of([&] { nnao::NnaoWeights::load(p); }), p, std::string("'") + tensor + "'");
    }
  const std::string p = path("tiny.blob");
  with_value(good, "feature_std", 3, 1e-45f).save(p);  // positive, but overflows the folding
  expect_refused(error_of([&] { nnao::NnaoWeights::load(p); }), p, "'feature_std'");
}

// A window of 4294967303 read as 7; a radius of 1e39 as inf.
TEST_F(ModelBlobTest, NnaoChecksKeysAsStoredBeforeNarrowing) {
  for (auto [key, value] : std::initializer_list<std::pair<const char*, const char*>>{{"window", "4294967303"},
                                                                                      {"hidden", "4294967300"},
                                                                                      {"radius", "1e39"},
                                                                                      {"radius", "nan"},
                                                                                      {"radius", "-inf"},
                                                                                      {"radius", "-1"}}) {
    Blob b = fixtures::random_nnao_blob(7, 4, 3);
    b.set_config(key, std::string(value));
    const std::string p = path("bad.blob");
    b.save(p);
    expect_refused(error_of([&] { nnao::NnaoWeights::load(p); }), p, key);
  }
  Blob h = fixtures::spread_nnao_outputs(fixtures::random_nnao_blob(0, 4, 4, false, {8, 8, 4}), 10, -0.3f);
  for (auto [key, value] : std::initializer_list<std::pair<const char*, const char*>>{
           {"directions", "4294967304"}, {"blur_depth", "inf"}, {"blur_passes", "4294967297"}}) {
    Blob b = h;
    b.set_config(key, std::string(value));
    const std::string p = path("bad.blob");
    b.save(p);
    expect_refused(error_of([&] { nnao::NnaoWeights::load(p); }), p, key);
  }
}

// level_head > 0: with a frame-level head (and the linear residual it scales).
gi::LoadedGenerator tiny_generator_blob(const std::string& p, int level_head = 0, bool level_energy = false) {
  gi::GeneratorConfig gc;
  gi::GiInputConfig in;
  in.size = 16;
  gc.unet.in_channels = in.channels();
  gc.unet.ngf = 2;
  gc.unet.levels = 2;
  gc.unet.dropout_blocks = 1;
  gc.unet.level_head = level_head;
  gc.unet.level_energy = level_energy;
  if (level_head > 0) gc.residual = gi::GiResidual::linear;
  Rng rng(1);
  auto G = gi::make_generator<float>(gc, rng);
  gi::save_generator_blob(p, *G, in, gc, "gan");
  return gi::load_generator(p);
}

TEST_F(ModelBlobTest, GiGeneratorKeepsItsLevelHeadAndOldBlobsReadWithout) {
  const std::string p = path("G.blob");
  EXPECT_EQ(tiny_generator_blob(p, 5).config.unet.level_head, 5);
  EXPECT_EQ(tiny_generator_blob(path("old.blob")).config.unet.level_head, 0);
  // a level_head key without the head's tensors (or with another width) is refused
  Blob b = Blob::load(p);
  b.set_config("level_head", int64_t(6));
  b.save(path("bad.blob"));
  expect_refused(error_of([&] { gi::load_generator(path("bad.blob")); }), path("bad.blob"), "level_head");
}

// The head's energy features widen its first layer by 6: the key travels with the blob,
// a blob without it reads as before, and a key that does not fit the tensors is refused.
TEST_F(ModelBlobTest, GiGeneratorKeepsItsLevelEnergyAndRefusesAKeyThatDoesNotFit) {
  const std::string p = path("G.blob");
  const gi::LoadedGenerator g = tiny_generator_blob(p, 5, true);
  EXPECT_EQ(g.config.unet.level_head, 5);
  EXPECT_TRUE(g.config.unet.level_energy);
  EXPECT_FALSE(tiny_generator_blob(path("moments.blob"), 5).config.unet.level_energy);
  for (const char* value : {"off", "maybe"}) {
    Blob b = Blob::load(p);
    b.set_config("level_energy", std::string(value));
    b.save(path("bad.blob"));
    expect_refused(error_of([&] { gi::load_generator(path("bad.blob")); }), path("bad.blob"),
                   value == std::string("off") ? "level_head_in" : "level_energy");
  }
}

// gi-infer and eval-gi accepted a NaN conv weight.
TEST_F(ModelBlobTest, GiGeneratorAndDiscriminatorRefuseANonFiniteTensorNamingIt) {
  const std::string p = path("G.blob");
  tiny_generator_blob(p);
  const Blob good = Blob::load(p);
  std::string conv, running_var;
  for (auto& [n, t] : good.tensors()) {
    if (conv.empty() && n.find("weight") != std::string::npos && t.dims.size() == 4) conv = n;
    if (running_var.empty() && n.find("running_var") != std::string::npos) running_var = n;
  }
  ASSERT_FALSE(conv.empty());
  ASSERT_FALSE(running_var.empty());
  for (const std::string& tensor : {conv, running_var})
    for (float bad : {std::nanf(""), HUGE_VALF}) {
      const std::string q = path("bad_G.blob");
      with_value(good, tensor, 0, bad).save(q);
      expect_refused(error_of([&] { gi::load_generator(q); }), q, "tensor '" + tensor + "'");
    }

  Rng rng(2);
  gi::PatchGan<float> D(gi::PatchGanConfig{15, 2, 2}, rng);
  gi::save_discriminator_blob(path("D.blob"), D);
  const Blob d = Blob::load(path("D.blob"));
  const std::string first = d.tensors().front().first;
  with_value(d, first, 0, -HUGE_VALF).save(path("bad_D.blob"));
  expect_refused(error_of([&] { gi::load_discriminator(path("bad_D.blob")); }), path("bad_D.blob"),
                 "tensor '" + first + "'");
}

TEST_F(ModelBlobTest, GiGeneratorChecksKeysAsStoredBeforeNarrowing) {
  const std::string p = path("G.blob");
  tiny_generator_blob(p);
  const Blob good = Blob::load(p);
  for (auto [key, value] : std::initializer_list<std::pair<const char*, const char*>>{{"size", "4294967312"},
                                                                                      {"ngf", "4294967298"},
                                                                                      {"levels", "4294967298"},
                                                                                      {"depth_max", "1e39"},
                                                                                      {"hdr_scale", "0"},
                                                                                      {"hdr_scale", "nan"},
                                                                                      {"dropout", "inf"},
                                                                                      {"light_max", "1e39"}}) {
    Blob b = good;
    b.set_config(key, std::string(value));
    const std::string q = path("bad_G.blob");
    b.save(q);
    expect_refused(error_of([&] { gi::load_generator(q); }), q, key);
  }
  Rng rng(2);
  gi::PatchGan<float> D(gi::PatchGanConfig{15, 2, 2}, rng);
  gi::save_discriminator_blob(path("D.blob"), D);
  Blob d = Blob::load(path("D.blob"));
  d.set_config("layers", std::string("4294967298"));
  d.save(path("bad_D.blob"));
  expect_refused(error_of([&] { gi::load_discriminator(path("bad_D.blob")); }), path("bad_D.blob"), "layers");
}

}  // namespace
