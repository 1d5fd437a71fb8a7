#pragma once
// Training NNAO (paper, section 4): points from the train split (nnao_points.h),
// standardised with train-set statistics, mini-batches of 16 drawn by a shuffled pass
// per epoch, loss = MSE + gamma * sum|theta| (eq. 2, gamma = 0.01), Adam.
//
// Every epoch: the mean training loss and the test MSE (in AO units, on the test split
// standardised with the *train* statistics) go to OUT/metrics.jsonl and the loss chart
// OUT/loss.svg; a checkpoint (weights, dropout Rng, Adam state, data Rng, epoch) goes
// to OUT/checkpoint.nnao.ckpt. --resume reloads it and continues: the points are rebuilt
// from the same seed, so an interrupted-and-resumed run ends bitwise equal to an
// uninterrupted one. Output: OUT/nnao.blob (nnao_weights.h describes it).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "core/progress.h"
#include "data/chart.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "models/nnao/nnao_fast_step.h"
#include "models/nnao/nnao_metrics.h"
#include "models/nnao/nnao_model.h"
#include "models/nnao/nnao_points.h"
#include "nn/serialize.h"
#include "optim/adam.h"
#include "optim/checkpoint.h"

namespace nns::nnao {

struct TrainOptions {
  std::string data_dir;  // train/ + test/ (or flat: split by scene)
  std::string out_dir = "nnao-out";
  NnaoNetConfig net;
  int epochs = 20;
  int batch = 16;
  double lr = 1e-3;
  double gamma = 0.01;
  int points_per_view = 1024;
  int test_points_per_view = 1024;
  float radius = 0;  // <= 0: each view's aoRadius
  uint64_t seed = 1;
  bool resume = false;
  bool quiet = false;
};

struct TrainResult {
  int64_t train_points = 0, test_points = 0, steps = 0;
  double train_loss = 0, test_mse = 0, seconds = 0;
  double step_microseconds = 0;  // training steps only (no data building, no test pass)
};

// Reads the views of a split and builds their points. One Rng stream per view, so a
// view's points do not depend on the views before it.
inline PointSet build_points(const std::vector<std::string>& paths, const TrainOptions& o,
                             int per_view, uint64_t stream) {
  PointSet ps;
  ps.window = o.net.window;
  ps.features = feature_count(o.net.window);
  ps.reserve(int64_t(paths.size()) * per_view);
  Rng base(o.seed ^ (0x9E37ull * stream));
  for (size_t i = 0; i < paths.size(); ++i) {
    data::View v = data::read_view(paths[i]);
    Rng rng = base.fork(i);
    add_view_points(ps, v, per_view, o.radius, rng);
  }
  return ps;
}

// Mean squared error in AO units over a standardised point set (eval mode, no graph).
inline double evaluate_mse(NnaoNet<float>& net, const PointSet& ps, float target_std) {
  if (ps.count == 0) return std::nan("");
  NoGradGuard ng;
  const bool was_training = net.is_training();
  net.eval();
  const int64_t F = ps.features, chunk = 1024;
  double se = 0;
  for (int64_t b = 0; b < ps.count; b += chunk) {
    const int64_t n = std::min(chunk, ps.count - b);
    Tensor<float> x({n, F});
    to_float(ps.x.data() + b * F, x.data(), n * F);
    Var<float> out = net.forward(Var<float>(x));
    for (int64_t i = 0; i < n; ++i) {
      double d = double(out.value()[i]) - ps.y[size_t(b + i)];
      se += d * d;
    }
  }
  net.train(was_training);
  return se / double(ps.count) * double(target_std) * target_std;
}

inline void copy_standardizer(NnaoNet<float>& net, const Standardizer& s) {
  std::copy(s.mean.begin(), s.mean.end(), net.feature_mean->data());
  std::copy(s.std.begin(), s.std.end(), net.feature_std->data());
  (*net.target_stats)[0] = s.target_mean;
  (*net.target_stats)[1] = s.target_std;
}

inline std::map<std::string, std::string> blob_config(const TrainOptions& o) {
  auto d = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return std::string(b);
  };
  return {{"window", std::to_string(o.net.window)}, {"hidden", std::to_string(o.net.hidden)},
          {"radius", d(o.radius > 0 ? o.radius : 0)}, {"dropout", d(o.net.dropout)},
          {"gamma", d(o.gamma)}, {"lr", d(o.lr)}, {"batch", std::to_string(o.batch)},
          {"epochs", std::to_string(o.epochs)}, {"seed", std::to_string(o.seed)},
          {"points_per_view", std::to_string(o.points_per_view)}, {"target", "ao"}};
}

inline TrainResult train_nnao(const TrainOptions& o) {
  namespace fs = std::filesystem;
  auto t_start = std::chrono::steady_clock::now();
  if (o.batch < 1 || o.epochs < 0 || o.net.window < 1 || o.net.hidden < 1 || o.net.hidden > 64 ||
      o.points_per_view < 1 || !(o.net.dropout >= 0 && o.net.dropout < 1))
    throw std::invalid_argument("train-nnao: batch, epochs, window, hidden (1..64), points per view or dropout out of range");
  data::DatasetListing d = data::list_dataset(o.data_dir);
  if (d.flat) d = data::split_flat_by_scene(d, 0.2);
  if (d.train.views.empty()) throw std::runtime_error(o.data_dir + ": no training views (*.exr) found");
  fs::create_directories(o.out_dir);
  auto say = [&](const std::string& s) {
    if (!o.quiet) std::fprintf(stderr, "%s\n", s.c_str());
  };

  say("building training points: " + std::to_string(d.train.views.size()) + " views x " +
      std::to_string(o.points_per_view) + " pixels, " + std::to_string(feature_count(o.net.window)) +
      " features each");
  PointSet train = build_points(d.train.views, o, o.points_per_view, 1);
  PointSet test = build_points(d.test.views, o, o.test_points_per_view, 2);
  Standardizer st = fit_standardizer(train);
  apply_standardizer(train, st);
  apply_standardizer(test, st);

  Rng init_rng(o.seed);
  NnaoNet<float> net(init_rng, o.net);
  copy_standardizer(net, st);
  AdamOptions ao;
  ao.lr = o.lr;
  Adam<float> opt(net.parameters(), ao);
  Rng data_rng = init_rng.fork(77);
  int64_t epoch = 0, step = 0;
  Checkpoint<float> ck;
  ck.add_module("net", net).add_optimizer("adam", opt).add_rng("data", data_rng)
      .add_counter("epoch", epoch).add_counter("step", step);
  const std::string ck_path = (fs::path(o.out_dir) / "checkpoint.nnao.ckpt").string();
  const std::string metrics_path = (fs::path(o.out_dir) / "metrics.jsonl").string();
  std::vector<std::string> metrics_lines;
  std::vector<double> ep_x, tr_y, te_y;
  if (o.resume) {
    if (!fs::exists(ck_path))
      throw std::runtime_error(ck_path + ": no checkpoint to resume from");
    ck.load(ck_path);
    // Keep the metrics of the epochs the checkpoint covers.
    std::ifstream mf(metrics_path);
    ResumedMetrics kept = read_resumed_metrics(mf, epoch);
    metrics_lines = std::move(kept.lines);
    ep_x = std::move(kept.epoch), tr_y = std::move(kept.train_loss), te_y = std::move(kept.test_mse);
    say("resuming from " + ck_path + " at epoch " + std::to_string(epoch));
  }

  TrainResult res;
  res.train_points = train.count;
  res.test_points = test.count;
  const int64_t F = train.features, B = o.batch;
  const int64_t steps_per_epoch = train.count / B;  // full batches only
  if (steps_per_epoch == 0) throw std::runtime_error("fewer training points than one batch");
  std::vector<int64_t> perm(size_t(train.count));
  auto params = net.parameters();
  NnaoFastStep fast(net, o.batch);
  std::vector<float> xb(static_cast<size_t>(B * F)), yb(static_cast<size_t>(B));
  Progress bar("train-nnao", (o.epochs - epoch) * steps_per_epoch);
  int64_t done = 0;
  double step_seconds = 0;
  int64_t timed_steps = 0;
  net.train();
  const int threads = num_threads();
  for (; epoch < o.epochs;) {
    for (int64_t i = 0; i < train.count; ++i) perm[size_t(i)] = i;
    for (int64_t i = train.count - 1; i > 0; --i)
      std::swap(perm[size_t(i)], perm[size_t(data_rng.below(uint64_t(i + 1)))]);
    double loss_sum = 0;
    // The step is ~20 us of work: waking a second core for it costs more than it saves
    // (the results are the same either way), so the steps run on one thread.
    set_num_threads(1);
    auto t0 = std::chrono::steady_clock::now();
    for (int64_t s = 0; s < steps_per_epoch; ++s) {
      for (int64_t b = 0; b < B; ++b) {
        const int64_t p = perm[size_t(s * B + b)];
        to_float(train.x.data() + p * F, xb.data() + b * F, F);
        yb[size_t(b)] = train.y[size_t(p)];
      }
      for (auto& prm : params) prm.grad_buffer().zero();
      loss_sum += fast.forward_backward(xb.data(), yb.data(), float(o.gamma));
      opt.step();
      ++step;
      ++done;
      if (!o.quiet && (s % 256 == 0 || s + 1 == steps_per_epoch)) {
        char status[80];
        std::snprintf(status, sizeof status, "epoch %lld loss %.4f", (long long)epoch + 1,
                      loss_sum / double(s + 1));
        bar.update(done, status);
      }
    }
    step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    set_num_threads(threads);
    timed_steps += steps_per_epoch;
    ++epoch;
    res.train_loss = loss_sum / double(steps_per_epoch);
    res.test_mse = evaluate_mse(net, test, st.target_std);
    char line[256];
    std::snprintf(line, sizeof line,
                  "{\"epoch\": %lld, \"train_loss\": %.8g, \"test_mse\": %.8g, \"steps\": %lld}",
                  (long long)epoch, res.train_loss, res.test_mse, (long long)step);
    metrics_lines.push_back(line);
    ep_x.push_back(double(epoch));
    tr_y.push_back(res.train_loss);
    te_y.push_back(res.test_mse);
    std::string all;
    for (auto& l : metrics_lines) all += l + "\n";
    data::write_text_atomic(metrics_path, all);
    data::ChartOptions co;
    co.title = "NNAO training";
    co.x_label = "epoch";
    co.y_label = "loss";
    co.log_y = true;
    data::write_chart((fs::path(o.out_dir) / "loss.svg").string(),
                      {{"train loss (MSE + gamma|theta|, standardised)", ep_x, tr_y, {}},
                       {"test MSE (AO units)", ep_x, te_y, {}}},
                      co);
    Blob meta("nnao-checkpoint");
    for (auto& [k, v] : blob_config(o)) meta.set_config(k, v);
    ck.save(ck_path, meta);
  }
  if (!o.quiet) bar.finish();
  save_weights((fs::path(o.out_dir) / "nnao.blob").string(), net, "nnao", blob_config(o));
  if (o.epochs > 0 && ep_x.empty() == false) res.test_mse = te_y.back();
  res.steps = step;
  res.step_microseconds = timed_steps ? 1e6 * step_seconds / double(timed_steps) : 0;
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return res;
}

}  // namespace nns::nnao
