#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "nn/functional/activations.h"
#include "nn/functional/elementwise.h"
#include "nn/functional/reduce.h"
#include "nn/linear.h"
#include "optim/adam.h"
#include "optim/checkpoint.h"
#include "optim/sgd.h"

using namespace nns;

namespace {

// A model whose forward draws from its own Rng and updates a buffer, so a resumed run
// only matches if both are restored too.
struct NoisyMlp : Module<float> {
  explicit NoisyMlp(uint64_t seed) {
    Rng init(seed);
    fc1 = register_module("fc1", std::make_shared<Linear<float>>(init, 4, 8));
    fc2 = register_module("fc2", std::make_shared<Linear<float>>(init, 8, 1));
    noise = &register_rng("noise", seed + 1);
    seen = &register_buffer("seen", Tensor<float>::zeros({1}));
  }
  Var<float> forward(const Var<float>& x) override {
    Var<float> h = tanh(fc1->forward(x));
    Tensor<float> n(h.shape());
    for (auto& v : n) v = float(0.05 * noise->normal());
    (*seen)[0] += float(x.size(0));
    return fc2->forward(h + Var<float>(n));
  }
  std::shared_ptr<Linear<float>> fc1, fc2;
  Rng* noise;
  Tensor<float>* seen;
};

// One training step on a batch drawn from `data`: y = sum of the inputs.
void train_step(NoisyMlp& m, Optimizer<float>& opt, Rng& data) {
  Tensor<float> x({8, 4}), y({8, 1});
  for (int64_t b = 0; b < 8; ++b) {
    float s = 0;
    for (int64_t k = 0; k < 4; ++k) s += x[b * 4 + k] = float(data.normal());
    y[b] = s;
  }
  opt.zero_grad();
  Var<float> loss = mean(square(m.forward(Var<float>(x)) - Var<float>(y)));
  loss.backward();
  opt.step();
}

struct TrainingRun {
  NoisyMlp model;
  Adam<float> adam;
  Sgd<float> sgd;  // a second optimizer over the same parameters, stepped in turn
  Rng data;
  int64_t step = 0, epoch = 0;
  Checkpoint<float> ck;

  explicit TrainingRun(uint64_t seed)
      : model(seed),
        adam(model.parameters(), {.lr = 1e-2, .beta1 = 0.5}),
        sgd(model.parameters(), {.lr = 1e-3, .momentum = 0.9}),
        data(seed + 100) {
    ck.add_module("model", model)
        .add_optimizer("adam", adam)
        .add_optimizer("sgd", sgd)
        .add_rng("data", data)
        .add_counter("step", step)
        .add_counter("epoch", epoch);
  }
  void advance(int64_t to) {
    for (; step < to; ++step) {
      train_step(model, step % 2 ? static_cast<Optimizer<float>&>(sgd) : adam, data);
      if (step % 5 == 4) ++epoch;
    }
  }
};

std::string temp_path(const std::string& name) {
  return "/tmp/nns_checkpoint_" + std::to_string(::getpid()) + "_" + name;
}

}  // namespace

TEST(Checkpoint, ResumedRunContinuesBitwise) {
  std::string p = temp_path("run.ckpt");
  TrainingRun straight(1);
  straight.advance(10);
  Blob meta("noisy-mlp");
  meta.set_config("note", "halfway");
  straight.ck.save(p, meta);
  straight.advance(25);

  TrainingRun resumed(99);  // different initial weights, noise and data: all must be overwritten
  Blob back = resumed.ck.load(p);
  EXPECT_EQ(back.kind(), "noisy-mlp");
  EXPECT_EQ(back.config_string("note"), "halfway");
  EXPECT_EQ(resumed.step, 10);
  EXPECT_EQ(resumed.epoch, 2);
  resumed.advance(25);

  auto a = straight.model.named_parameters(), b = resumed.model.named_parameters();
  for (size_t i = 0; i < a.size(); ++i)
    for (int64_t k = 0; k < a[i].second.numel(); ++k)
      ASSERT_EQ(a[i].second.value()[k], b[i].second.value()[k]) << a[i].first << "[" << k << "]";
  EXPECT_EQ((*straight.model.seen)[0], (*resumed.model.seen)[0]);
  EXPECT_EQ(straight.data.state(), resumed.data.state());
  EXPECT_EQ(straight.adam.steps(0), resumed.adam.steps(0));
  std::remove(p.c_str());
}

TEST(Checkpoint, WithoutRestoringTheRunDiverges) {
  // The control for the test above: same start, but the optimizer state is not
  // restored, and the weights must differ.
  std::string p = temp_path("partial.ckpt");
  TrainingRun straight(1);
  straight.advance(10);
  straight.ck.save(p);
  straight.advance(25);

  TrainingRun resumed(99);
  Checkpoint<float> partial;
  partial.add_module("model", resumed.model)
      .add_rng("data", resumed.data)
      .add_counter("step", resumed.step)
      .add_counter("epoch", resumed.epoch);
  partial.load(p);
  resumed.advance(25);
  bool differs = false;
  auto a = straight.model.parameters(), b = resumed.model.parameters();
  for (size_t i = 0; i < a.size(); ++i)
    for (int64_t k = 0; k < a[i].numel(); ++k) differs |= a[i].value()[k] != b[i].value()[k];
  EXPECT_TRUE(differs);
  std::remove(p.c_str());
}

TEST(Checkpoint, MissingEntryIsNamed) {
  std::string p = temp_path("small.ckpt");
  TrainingRun r(1);
  Checkpoint<float> only_model;
  only_model.add_module("model", r.model);
  only_model.save(p);
  try {
    r.ck.load(p);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'optim.adam.lr' is missing"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
  std::remove(p.c_str());
}

// fuzz_checkpoint found a checkpoint whose saved learning rate was negative: set_lr's
// invalid_argument escaped naming no file. A saved lr that is no learning rate is now
// an error naming the blob, for Adam and SGD alike. A GAN checkpoint's lr of 1e300 was
// resumed and trained on: a rate above the --lr flags' ceiling (1e9) is none either; a
// NaN or an infinity is refused as non-finite by the blob itself.
TEST(Checkpoint, ASavedLearningRateThatIsNoneIsRefusedNamingTheFile) {
  for (double bad : {-4046.848, std::nan(""), HUGE_VAL, 1e300, 1.5e9}) {
    Rng init(1);
    Linear<float> net(init, 3, 2);
    Adam<float> adam(net.parameters());
    Sgd<float> sgd(net.parameters(), SgdOptions{});
    Blob b("checkpoint");
    adam.save_state(b, "a.");
    sgd.save_state(b, "s.");
    Blob tampered("checkpoint");
    for (auto& [name, t] : b.tensors()) {
      if (name == "a.lr" || name == "s.lr") tampered.put_f64(name, bad);
      else {
        const Shape shape(t.dims.begin(), t.dims.end());
        const char* d = t.bytes.data();
        switch (t.dtype) {
          case DType::F32:
            tampered.put(name, shape, reinterpret_cast<const float*>(d));
            break;
          case DType::F64:
            tampered.put(name, shape, reinterpret_cast<const double*>(d));
            break;
          case DType::I64:
            tampered.put(name, shape, reinterpret_cast<const int64_t*>(d));
            break;
          case DType::U64:
            tampered.put(name, shape, reinterpret_cast<const uint64_t*>(d));
            break;
        }
      }
    }
    Blob loaded = Blob::parse(tampered.serialize(), "run/checkpoint.blob");
    for (Optimizer<float>* o : std::initializer_list<Optimizer<float>*>{&adam, &sgd}) {
      try {
        o->load_state(loaded, o == &adam ? "a." : "s.");
        ADD_FAILURE() << "lr " << bad << " accepted";
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("run/checkpoint.blob"), std::string::npos) << e.what();
        const char* why = std::isfinite(bad) ? "not a learning rate" : "non-finite";
        EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
      }
    }
  }
}
