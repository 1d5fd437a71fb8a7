// One pix2pix step's gradients (runs/gi/gan_trainer.h): the discriminator's gradient is
// that of the discriminator loss alone. It used to also hold the adversarial term of the
// generator loss, because D was unfrozen before the generator's backward pass ran and
// ops decide at backward time whether a parent wants a gradient.
#include <gtest/gtest.h>

#include <cstring>

#include "runs/gi/gan_trainer.h"

namespace {

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

TEST(GanStep, DiscriminatorGradientIsTheDiscriminatorLossAlone) {
  GanTrainConfig c;
  c.inputs.mode = GiMode::front;
  c.inputs.size = 16;
  c.ngf = 4, c.ndf = 4, c.levels = 3, c.d_layers = 2;
  GanTrainer t(c);
  GiSample s;
  Rng r(2);
  s.input = Tensor<float>({1, c.inputs.channels(), 16, 16});
  s.target = Tensor<float>({1, 3, 16, 16});
  for (int64_t i = 0; i < s.input.numel(); ++i) s.input[i] = float(r.uniform() * 2 - 1);
  for (int64_t i = 0; i < s.target.numel(); ++i) s.target[i] = float(r.uniform() * 2 - 1);
  s.front = {0, 0, 16, 16};

  std::vector<Rng> rngs;  // G's dropout: the recomputation below draws the same masks
  for (Rng* g : t.rngs()) rngs.push_back(*g);
  t.forward_backward(s, /*checked=*/true);
  std::vector<Tensor<float>> step_grads;
  for (auto& p : t.D->parameters()) step_grads.push_back(p.grad().clone());

  size_t k = 0;
  for (Rng* g : t.rngs()) *g = rngs[k++];
  Var<float> fake = crop2d(generate(t.G, c.generator(), Var<float>(s.input)), s.front);
  auto pair = [](const Var<float>& a, const Var<float>& b) { return concat_channels(std::vector<Var<float>>{a, b}); };
  Var<float> x_f(crop2d(s.input, s.front));
  Var<float> d_loss = (bce_with_logits_target(t.D->forward(pair(x_f, Var<float>(s.target))), 1.0f) +
                       bce_with_logits_target(t.D->forward(pair(x_f, Var<float>(fake.value()))), 0.0f)) *
                      0.5f;
  t.D->zero_grad();
  d_loss.backward();
  k = 0;
  for (auto& p : t.D->parameters()) {
    const Tensor<float>& want = p.grad();
    ASSERT_EQ(want.numel(), step_grads[k].numel());
    EXPECT_EQ(std::memcmp(want.data(), step_grads[k].data(), sizeof(float) * size_t(want.numel())), 0)
        << "D parameter " << k << ": the step's gradient is not the D loss's";
    ++k;
  }
}

}  // namespace
