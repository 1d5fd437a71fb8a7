#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <memory>

#include "nn/linear.h"
#include "nn/serialize.h"

using namespace nns;

namespace {

// A small tree: two Linear children, a buffer and an Rng of its own.
template <class T>
struct Net : Module<T> {
  Net(uint64_t seed, int64_t hidden, bool extra = false) {
    Rng rng(seed);
    fc1 = this->register_module("fc1", std::make_shared<Linear<T>>(rng, 3, hidden));
    fc2 = this->register_module("fc2", std::make_shared<Linear<T>>(rng, hidden, 2));
    if (extra) this->register_module("fc3", std::make_shared<Linear<T>>(rng, 2, 2));
    running = &this->register_buffer("running", Tensor<T>::full({2}, T(seed)));
    noise = &this->register_rng("noise", seed);
  }
  std::shared_ptr<Linear<T>> fc1, fc2;
  Tensor<T>* running;
  Rng* noise;
};

std::string temp_path(const std::string& name) {
  return "/tmp/nns_serialize_" + std::to_string(::getpid()) + "_" + name;
}

template <class F>
void expect_error(F&& f, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no error (expected '" << what << "')";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(Serialize, ModuleRoundTripRestoresEverythingBitwise) {
  std::string p = temp_path("net.blob"), q = temp_path("net2.blob");
  Net<float> a(1, 8), b(2, 8);
  a.noise->next_u64();
  save_weights(p, a, "net", {{"hidden", "8"}});
  Blob blob = load_weights(p, b, "net");
  EXPECT_EQ(blob.config_int("hidden"), 8);
  auto pa = a.named_parameters(), pb = b.named_parameters();
  ASSERT_EQ(pa.size(), 4u);
  for (size_t i = 0; i < pa.size(); ++i) {
    EXPECT_EQ(pa[i].first, pb[i].first);
    for (int64_t k = 0; k < pa[i].second.numel(); ++k)
      ASSERT_EQ(pa[i].second.value()[k], pb[i].second.value()[k]) << pa[i].first;
  }
  EXPECT_EQ((*b.running)[0], 1.0f);
  EXPECT_EQ(b.noise->state(), a.noise->state());
  save_weights(q, b, "net", {{"hidden", "8"}});
  EXPECT_EQ(read_file(p), read_file(q));
  std::remove(p.c_str());
  std::remove(q.c_str());
}

TEST(Serialize, NamesAreDotted) {
  Net<float> a(1, 4);
  Blob b;
  put_module(b, a);
  std::vector<std::string> names;
  for (auto& [n, t] : b.tensors()) names.push_back(n);
  EXPECT_EQ(names, (std::vector<std::string>{"fc1.weight", "fc1.bias", "fc2.weight", "fc2.bias", "running", "noise"}));
}

TEST(Serialize, MissingTensorIsNamed) {
  Net<float> small(1, 4), big(1, 4, /*extra=*/true);
  Blob b;
  put_module(b, small);
  expect_error([&] { get_module(b, big); }, "'fc3.weight' is missing");
}

TEST(Serialize, UnexpectedTensorIsNamed) {
  Net<float> small(1, 4), big(1, 4, /*extra=*/true);
  Blob b;
  put_module(b, big);
  expect_error([&] { get_module(b, small); }, "'fc3.weight' does not belong to the model");
}

TEST(Serialize, ShapeMismatchIsNamed) {
  Net<float> a(1, 4), b(1, 5);
  Blob blob;
  put_module(blob, a);
  expect_error([&] { get_module(blob, b); }, "'fc1.weight' has shape [4,3], expected [5,3]");
}

TEST(Serialize, WrongKindIsReported) {
  std::string p = temp_path("kind.blob");
  Net<float> a(1, 4);
  save_weights(p, a, "net");
  expect_error([&] { load_weights(p, a, "other"); }, "holds a 'net' model, expected 'other'");
  std::remove(p.c_str());
}

TEST(Serialize, FloatWeightsLoadIntoADoubleModel) {
  Net<float> a(1, 4);
  Net<double> b(2, 4);
  Blob blob;
  put_module(blob, a);
  get_module(blob, b);
  EXPECT_EQ(double(a.fc1->weight.value()[3]), b.fc1->weight.value()[3]);
}

TEST(Serialize, PrefixSelectsASubtree) {
  Net<float> a(1, 4), b(2, 4), c(3, 4);
  Blob blob;
  put_module(blob, a, "gen.");
  put_module(blob, c, "disc.");
  get_module(blob, b, "gen.");  // the "disc." tensors are not unexpected here
  EXPECT_EQ(a.fc2->bias.value()[1], b.fc2->bias.value()[1]);
}
