#pragma once
// The demo: the framework end to end in a few seconds, on built-in synthetic data.
//
// A small conv net (conv 3x3 -> batchnorm -> relu -> conv 3x3) learns an edge detector,
// |sobel_x * x| + |sobel_y * x|, on random smooth images: relu(a) + relu(-a) = |a|, so
// the net can represent the target exactly and the loss falls towards 0. Then the
// weights are saved as a blob (docs/weights-format.md), loaded into a fresh model, and
// the reloaded model must give bitwise the same validation loss.
//
//   demo                               default: 2 threads, 20 epochs, ./demo-out
//   demo --threads 1 --epochs 30 --out /tmp/demo
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/progress.h"
#include "core/thread_pool.h"
#include "nn/batchnorm.h"
#include "nn/conv2d.h"
#include "nn/functional/activations.h"
#include "nn/functional/elementwise.h"
#include "nn/functional/reduce.h"
#include "nn/serialize.h"
#include "optim/adam.h"
#include "optim/lr_schedule.h"
#include "models/edge_net.h"

namespace nns::runs {

constexpr int64_t kSize = 32;  // image height and width

// A batch of smooth random images (sums of Gaussian blobs) and their edge maps.
struct Batch {
  Tensor<float> x, y;
};
Batch make_batch(Rng& rng, int64_t n) {
  Batch b{Tensor<float>::zeros({n, 1, kSize, kSize}), Tensor<float>::zeros({n, 1, kSize, kSize})};
  for (int64_t k = 0; k < n; ++k) {
    float* img = b.x.data() + k * kSize * kSize;
    for (int blob = 0; blob < 4; ++blob) {
      double cx = rng.uniform(0, kSize), cy = rng.uniform(0, kSize);
      double r = rng.uniform(2, 7), a = rng.uniform(-1, 1);
      for (int64_t i = 0; i < kSize; ++i)
        for (int64_t j = 0; j < kSize; ++j)
          img[i * kSize + j] += float(a * std::exp(-((i - cy) * (i - cy) + (j - cx) * (j - cx)) / (2 * r * r)));
    }
    float* out = b.y.data() + k * kSize * kSize;
    auto at = [&](int64_t i, int64_t j) {
      return (i < 0 || j < 0 || i >= kSize || j >= kSize) ? 0.0f : img[i * kSize + j];
    };
    for (int64_t i = 0; i < kSize; ++i)
      for (int64_t j = 0; j < kSize; ++j) {
        float gx = at(i - 1, j + 1) + 2 * at(i, j + 1) + at(i + 1, j + 1) - at(i - 1, j - 1) - 2 * at(i, j - 1) -
                   at(i + 1, j - 1);
        float gy = at(i + 1, j - 1) + 2 * at(i + 1, j) + at(i + 1, j + 1) - at(i - 1, j - 1) - 2 * at(i - 1, j) -
                   at(i - 1, j + 1);
        out[i * kSize + j] = std::abs(gx) + std::abs(gy);
      }
  }
  return b;
}

float mse(EdgeNet& net, const Batch& b) {
  Var<float> d = net.forward(Var<float>(b.x)) - Var<float>(b.y);
  return mean(square(d)).value()[0];
}

// Trains, saves, reloads; returns the exit status (1 if the loss did not fall or the
// reloaded weights do not reproduce it bitwise).
inline int run_edge_demo(int threads, int seed, int epochs, int width, const std::string& out) {
  const int64_t batch = 8, steps_per_epoch = 16;
  EdgeNet net(uint64_t(seed), width);
  Adam<float> opt(net.parameters(), {.lr = 1e-2});
  // Constant for the first two thirds, then pix2pix's linear decay.
  LrSchedule schedule = LrSchedule::linear(1e-2, epochs - epochs / 3, epochs / 3);
  Rng data(uint64_t(seed) * 7919 + 1);
  Rng val_rng(12345);  // the same validation set for every seed
  const Batch val = make_batch(val_rng, 32);

  auto val_loss = [&] {
    NoGradGuard no_grad;
    net.eval();
    float l = mse(net, val);
    net.train();
    return l;
  };
  std::printf("demo: %lld parameters, %d threads, %d epochs of %lld batches of %lld %lldx%lld images\n",
              (long long)net.parameter_count(), threads, epochs, (long long)steps_per_epoch, (long long)batch,
              (long long)kSize, (long long)kSize);
  const float start_val = val_loss();
  std::printf("validation loss before training: %.5f\n", start_val);
  std::fflush(stdout);
  auto t0 = std::chrono::steady_clock::now();
  // One bar for the whole run: on a terminal it redraws in place, in a log it prints
  // a line every 10% — either way the loss is seen falling.
  Progress bar("train", int64_t(epochs) * steps_per_epoch);
  for (int epoch = 0; epoch < epochs; ++epoch) {
    schedule.apply(opt, epoch);
    double sum = 0;
    for (int64_t s = 0; s < steps_per_epoch; ++s) {
      Batch b = make_batch(data, batch);
      opt.zero_grad();
      Var<float> loss = mean(square(net.forward(Var<float>(b.x)) - Var<float>(b.y)));
      loss.backward();
      opt.step();
      sum += loss.value()[0];
      char status[80];
      std::snprintf(status, sizeof status, "epoch %d/%d train loss %.5f lr %.2g", epoch + 1, epochs,
                    sum / double(s + 1), opt.lr());
      bar.update(int64_t(epoch) * steps_per_epoch + s + 1, status);
    }
  }
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const float end_val = val_loss();
  std::printf("validation loss after training:  %.5f (%.1fx lower, %.1f s)\n", end_val, start_val / end_val, seconds);

  std::filesystem::create_directories(out);
  const std::string path = out + "/demo.blob";
  save_weights(path, net, "demo-edgenet", {{"width", std::to_string(width)}, {"seed", std::to_string(seed)}});
  EdgeNet reloaded(uint64_t(seed) + 1000, width);  // other initial weights: all must be overwritten
  Blob b = load_weights(path, reloaded, "demo-edgenet");
  reloaded.eval();
  float reloaded_val;
  {
    NoGradGuard no_grad;
    reloaded_val = mse(reloaded, val);
  }
  std::printf("saved %s (%lld bytes); reloaded model (width %lld from the blob's config): validation loss %.5f\n",
              path.c_str(), (long long)std::filesystem::file_size(path), (long long)b.config_int("width"),
              reloaded_val);
  if (std::memcmp(&reloaded_val, &end_val, sizeof(float)) != 0) {
    std::fprintf(stderr, "demo: error: the reloaded model gives %.9g, the trained one %.9g\n", reloaded_val, end_val);
    return 1;
  }
  if (!(end_val < start_val)) {
    std::fprintf(stderr, "demo: error: the validation loss did not fall\n");
    return 1;
  }
  std::printf("ok: the loss fell and the reloaded weights reproduce it bitwise\n");
  return 0;
}

}  // namespace nns::runs
