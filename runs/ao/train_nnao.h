#pragma once
// Training NNAO (paper, section 4): points from the train split (nnao_points.h),
// standardised with train-set statistics, mini-batches of 16 drawn by a shuffled pass
// per epoch, loss = MSE + gamma * sum|theta| (eq. 2, gamma = 0.01), Adam.
//
// The points of both splits live in unnamed files in the output folder, not in memory
// (runs/ao/row_file.h): the memory is the shuffle buffers (--shuffle-buffer-mb, two of
// them) whatever the number of views. The epoch's order is a chunked shuffle (chunks of
// --shuffle-chunk points in a shuffled order, loaded a buffer at a time, rows shuffled
// within the buffer); a buffer that holds every point gives the global shuffle.
//
// The loop body only; the run layer (runs/training_run.h) owns the folder, the log, the
// checkpoint and the non-finite stop. Every epoch: the mean training loss and the test
// MSE (in AO units, on the test split standardised with the *train* statistics) go to
// OUT/metrics.jsonl and the chart OUT/loss.svg; then OUT/nnao.blob (nnao_weights.h
// describes it) and OUT/checkpoint.blob (weights, dropout Rng, Adam state, data Rng,
// epoch, configuration). --resume continues from it: the points are rebuilt from the
// same seed, so an interrupted-and-resumed run ends bitwise equal to an uninterrupted
// one. A NaN or Inf loss stops the run (exit 3) with the last good model in place.
//
// --accumulate K: each step's batch is K micro-batches of batch/K points, their gradients
// averaged in micro-batch order (runs/distributed/grad_sync.h); under mpirun the
// micro-batches are spread over the ranks, with the same numbers for any rank count.
// The point building is sharded: view i is read and its features computed by rank
// i % N only, its rows then broadcast (build_points), so every rank ends with the same
// point files as one process, bitwise, for 1/N of the feature work. Every rank reads
// every row of a step (the shuffle is one stream), and computes only its micro-batches.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "core/atomic_file.h"
#include "report/chart.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/kept_views.h"
#include "data/require_valid_dataset.h"
#include "data/validation_split.h"
#include "models/nnao/nnao_fast_step.h"
#include "models/nnao/nnao_model.h"
#include "runs/ao/nnao_points.h"
#include "runs/ao/nnao_train_options.h"
#include "runs/available_memory.h"
#include "nn/serialize.h"
#include "optim/adam.h"
#include "optim/checkpoint.h"
#include "runs/distributed/grad_sync.h"
#include "runs/distributed/world.h"
#include "runs/training_loop.h"

namespace nns::runs {

// Reads the views of a split and appends their points to a file in the output folder, in
// view order; `sums` (if any) accumulates the standardiser's statistics on the way. One
// Rng stream per view, so a view's points do not depend on the views before it.
//
// Under mpirun the reading and the features (the cost: minutes, against seconds per
// epoch) are shared out: view i is built by rank i % N alone, then its rows are
// broadcast, so every rank ends with the same file, bitwise, as one process. The views go
// in rounds of N (each rank builds its one view of the round, then the round's rows are
// broadcast in view order), so a rank holds at most N views' rows. A view that fails on
// its owner throws there; the failing rank's Session::finish calls MPI_Abort, which ends
// the ranks waiting for that view in the broadcast (no hang).
struct BuildShare {
  int64_t views_built = 0;      // by this rank itself
  double exchange_seconds = 0;  // in the broadcasts, waiting for the owners included
};
inline PointFile build_points(const std::vector<std::string>& paths, const TrainOptions& o, int per_view,
                              uint64_t stream, const std::string& name, StandardizerSums* sums, BuildShare& share,
                              data::KeptViews& kept) {
  PointFile pf;
  pf.input = o.net.input();
  pf.features = pf.input.count();
  const int64_t R = point_row_bytes(pf.features);
  pf.rows = runs::RowFile(o.out_dir, name, R);
  Rng base(o.seed ^ (0x9E37ull * stream));
  const size_t ranks = size_t(runs::size()), me = size_t(runs::rank());
  // For the failing-owner test (tests/distributed): the view of this file name fails on
  // its owner alone, after the dataset check every rank passed.
  const char* fail = std::getenv("NNSHADE_TEST_FAIL_POINT_VIEW");
  std::vector<std::vector<char>> round(ranks);  // round[r]: the rows of rank r's view
  for (size_t first = 0; first < paths.size(); first += ranks) {
    const size_t end = std::min(paths.size(), first + ranks);
    // first is a multiple of N, so view i of the round is round[i % N], built by rank i % N.
    if (first + me < end) {
      const size_t i = first + me;
      if (fail && std::filesystem::path(paths[i]).filename() == fail)
        throw std::runtime_error(paths[i] + ": NNSHADE_TEST_FAIL_POINT_VIEW");
      data::View v = kept.complete() ? kept.take(paths[i]) : data::read_view(paths[i]);
      Rng rng = base.fork(i);
      view_points(v, pf.input, per_view, o.radius, rng, round[me], o.downsample);
      ++share.views_built;
    }
    const auto t0 = std::chrono::steady_clock::now();
    for (size_t i = first; i < end; ++i) runs::broadcast_bytes(round[i - first], int(i - first));
    share.exchange_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (size_t i = first; i < end; ++i) {
      const std::vector<char>& rows = round[i - first];
      const int64_t n = int64_t(rows.size()) / R;
      if (sums) sums->add(rows.data(), n);
      pf.rows.append(rows.data(), n);
    }
  }
  return pf;
}

// Mean squared error in AO units over a standardised point file (eval mode, no graph),
// read in order a block at a time.
inline double evaluate_mse(nnao::NnaoNet<float>& net, const PointFile& pf, float target_std) {
  if (pf.count() == 0) return std::nan("");
  NoGradGuard ng;
  const bool was_training = net.is_training();
  net.eval();
  const int64_t F = pf.features, R = point_row_bytes(F), chunk = 1024;
  std::vector<char> rows(size_t(std::min(chunk, pf.count()) * R));
  double se = 0;
  for (int64_t b = 0; b < pf.count(); b += chunk) {
    const int64_t n = std::min(chunk, pf.count() - b);
    pf.rows.read_rows(b, n, rows.data());
    Tensor<float> x({n, F});
    for (int64_t i = 0; i < n; ++i) to_float(row_features(rows.data() + i * R), x.data() + i * F, F);
    Var<float> out = net.forward(Var<float>(x));
    for (int64_t i = 0; i < n; ++i) {
      double d = double(out.value()[i]) - row_target(rows.data() + i * R, F);
      se += d * d;
    }
  }
  net.train(was_training);
  return se / double(pf.count()) * double(target_std) * target_std;
}

// Rows per shuffle buffer: --shuffle-buffer-mb of rows, at least one.
inline int64_t shuffle_buffer_rows(const TrainOptions& o) {
  const double rows = o.shuffle_buffer_mb * 1048576.0 / double(point_row_bytes(o.net.inputs()));
  return std::max<int64_t>(1, int64_t(std::min(rows, 1e15)));
}

inline void copy_standardizer(nnao::NnaoNet<float>& net, const Standardizer& s) {
  std::copy(s.mean.begin(), s.mean.end(), net.feature_mean->data());
  std::copy(s.std.begin(), s.std.end(), net.feature_std->data());
  (*net.target_stats)[0] = s.target_mean;
  (*net.target_stats)[1] = s.target_std;
}

// A double as the blob records it: %.17g reads back as the same double.
inline std::string blob_config_double(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return std::string(b);
}

inline std::map<std::string, std::string> blob_config(const TrainOptions& o) {
  const auto d = blob_config_double;
  std::map<std::string, std::string> c = {{"window", std::to_string(o.net.window)},
                                          {"hidden", std::to_string(o.net.hidden)},
                                          {"radius", d(o.radius > 0 ? o.radius : 0)},
                                          {"dropout", d(o.net.dropout)},
                                          {"gamma", d(o.gamma)},
                                          {"lr", d(o.lr)},
                                          {"batch", std::to_string(o.batch)},
                                          {"epochs", std::to_string(o.epochs)},
                                          {"seed", std::to_string(o.seed)},
                                          {"points_per_view", std::to_string(o.points_per_view)},
                                          {"target", "ao"}};
  // A grid model's blob stays as it was (readers take a missing "features" as grid).
  if (o.net.input().is_horizon()) {
    c["features"] = "horizon";
    c["directions"] = std::to_string(o.net.horizon.directions);
    c["steps"] = std::to_string(o.net.horizon.steps);
    c["bands"] = std::to_string(o.net.horizon.bands);
    c["blur_passes"] = std::to_string(o.blur_passes);
    c["blur_depth"] = d(o.blur_depth);
    c["blur_normal_power"] = std::to_string(o.blur_normal_power);
    c["radius_term_max"] = d(o.radius_term_max);
    if (o.downsample != 1) c["downsample"] = std::to_string(o.downsample);  // absent: 1, as before it existed
    c["target"] = "ao-minus-horizon-visibility";
  }
  return c;
}

// What the checkpoint records and a --resume must match (runs/training_run.h): the
// model, the optimisation, the seed and the data (its folder and view counts).
inline runs::RunSpec run_spec(const TrainOptions& o, const data::DatasetListing& d) {
  runs::RunSpec spec;
  spec.app = "train-nnao";
  spec.out = o.out_dir;
  spec.checkpoint_kind = "nnao-checkpoint";
  spec.resume = o.resume;
  for (auto& [k, v] : blob_config(o)) spec.config.emplace_back(k, v);
  // Horizon checkpoints made before --blur-passes existed blurred once.
  spec.unrecorded_means.emplace_back("blur_passes", "1");
  // ... and before --blur-depth and --blur-normal-power, used the first edge terms.
  spec.unrecorded_means.emplace_back("blur_depth", blob_config_double(0.1));
  spec.unrecorded_means.emplace_back("blur_normal_power", "8");
  spec.unrecorded_means.emplace_back("radius_term_max", blob_config_double(0));
  spec.unrecorded_means.emplace_back("downsample", "1");
  spec.config.emplace_back("test_points_per_view", std::to_string(o.test_points_per_view));
  // They set the order of every epoch, so a resume with others would not replay it.
  spec.config.emplace_back("shuffle_chunk", std::to_string(o.shuffle_chunk));
  spec.config.emplace_back("shuffle_buffer_rows", std::to_string(shuffle_buffer_rows(o)));
  spec.config.emplace_back("data", std::filesystem::weakly_canonical(o.data_dir).string());
  spec.config.emplace_back("train_views", std::to_string(d.train.views.size()));
  spec.config.emplace_back("test_views", std::to_string(d.test.views.size()));
  spec.config.emplace_back("validation_fraction", std::to_string(o.validation_fraction));
  std::string fams;
  for (auto& f : o.validation_families) fams += (fams.empty() ? "" : ",") + f;
  spec.config.emplace_back("validation_families", fams);
  // Checkpoints made before --precision existed lack it: RunSpec::unrecorded_means.
  spec.config.emplace_back("precision", precision_name(o.precision));
  // It changes the rounding; checkpoints older than --accumulate lack it (RunSpec::unrecorded_means).
  spec.config.emplace_back("accumulate", std::to_string(o.accumulate));
  return spec;
}

// OUT/loss.svg (the training loss, on standardised targets, with the L1 penalty) and
// OUT/mse.svg (test and validation MSE in AO units), .png beside each: two quantities in
// two units, so each on an axis of its own.
inline void write_loss_chart(runs::TrainingRun& run) {
  const auto& log = run.metrics();
  report::ChartOptions co;
  co.title = "NNAO training loss";
  co.x_label = "epoch";
  co.y_label = "MSE + gamma |theta| (standardised)";
  co.log_y = true;
  report::write_chart(run.path("loss.svg"), {{"train loss", log.series("epoch"), log.series("train_loss"), {}}}, co);
  co.title = "NNAO held-out error";
  co.y_label = "MSE (AO units)";
  std::vector<report::ChartSeries> mse = {{"test MSE", log.series("epoch"), log.series("test_mse"), {}}};
  const std::vector<double> val = log.series("val_mse");
  if (std::any_of(val.begin(), val.end(), [](double v) { return std::isfinite(v); }))
    mse.push_back({"validation MSE", log.series("epoch"), log.series("val_mse"), {}});
  report::write_chart(run.path("mse.svg"), mse, co);
}

// The options train_nnao refuses before it reads anything.
inline void check_options(const TrainOptions& o) {
  if (const std::string p = o.net.input().problem(); !p.empty()) throw std::invalid_argument("train-nnao: " + p);
  if (o.batch < 1 || o.epochs < 0 || o.net.window < 1 || o.net.hidden < 1 || o.net.hidden > 64 ||
      o.points_per_view < 1 || !(o.net.dropout >= 0 && o.net.dropout < 1) || o.shuffle_chunk < 1 ||
      !(o.shuffle_buffer_mb > 0))
    throw std::invalid_argument(
        "train-nnao: batch, epochs, window, hidden (1..64), points per view, dropout or shuffle sizes out of range");
  if (o.downsample != 1 && (o.downsample != 2 && o.downsample != 4 || !o.net.input().is_horizon()))
    throw std::invalid_argument("train-nnao: --downsample " + std::to_string(o.downsample) +
                                " needs horizon features and 1, 2 or 4");
  if (o.accumulate < 1 || o.batch % o.accumulate != 0)
    throw std::invalid_argument("train-nnao: --accumulate " + std::to_string(o.accumulate) + " must divide --batch " +
                                std::to_string(o.batch));
}

// The dataset's views, checked: train (without validation), validation, test, and the
// views this rank builds points from as the check decoded them (each file decoded once),
// when they fit in half the memory available; else build_points reads them again.
struct NnaoData {
  data::TrainingSplits splits;
  std::unique_ptr<data::KeptViews> kept;
};

// The views build_points reads on this rank: view i of each split goes to rank i % N.
inline std::vector<std::string> views_built_here(const data::TrainingSplits& s) {
  std::vector<std::string> out;
  const size_t ranks = size_t(runs::size()), me = size_t(runs::rank());
  for (const auto* list : {&s.listing.train.views, &s.listing.test.views, &s.validation.views})
    for (size_t i = me; i < list->size(); i += ranks) out.push_back((*list)[i]);
  return out;
}

inline NnaoData open_data(const TrainOptions& o) {
  NnaoData d;
  try {
    d.splits = data::open_training_splits(o.data_dir, o.validation_fraction, o.validation_families);
  } catch (const std::exception&) {
    data::require_valid_dataset(o.data_dir, data::Purpose::nnao);  // the check's full report first
    throw;
  }
  d.kept = std::make_unique<data::KeptViews>(views_built_here(d.splits), default_memory_budget_gib() * double(1 << 30));
  data::require_valid_dataset(o.data_dir, data::Purpose::nnao, d.kept.get());
  if (o.validation_fraction > 0 && d.splits.validation.size() == 0)
    throw std::runtime_error(o.data_dir + ": cannot hold out validation scenes: the training split has a single scene");
  if (!d.kept->complete() && !o.quiet)
    std::fprintf(stderr, "train-nnao: views decoded again after the dataset check: %s\n", d.kept->reason().c_str());
  return d;
}

// The trained state, in the order its random numbers are drawn: the weights, then the
// data order's generator forked from the same seed; the checkpoint holds all of it.
struct NnaoModel {
  explicit NnaoModel(const TrainOptions& o)
      : init_rng(o.seed),
        net(init_rng, o.net),
        opt(net.parameters(), AdamOptions{.lr = o.lr}),
        data_rng(init_rng.fork(77)) {
    ck.add_module("net", net).add_optimizer("adam", opt).add_rng("data", data_rng);
  }
  Rng init_rng;
  nnao::NnaoNet<float> net;
  Adam<float> opt;
  Rng data_rng;
  Checkpoint<float> ck;
  int64_t step = 0;
};

// The standardised points of the three splits, in files in the output folder.
struct NnaoPoints {
  PointFile train, test, valid;
  Standardizer standardizer;
  int64_t views = 0;  // of the three splits
  BuildShare share;
  double seconds = 0;
};

// Built after the run layer has made the folder (they are written into it) and has
// accepted or refused a --resume (a refusal costs no feature building). They are rebuilt
// from the seed on every start, so a resume sees the same rows.
inline NnaoPoints build_all_points(const TrainOptions& o, NnaoData& d, nnao::NnaoNet<float>& net) {
  const data::TrainingSplits& s = d.splits;
  auto say = [&](const std::string& line) {
    if (!o.quiet) std::fprintf(stderr, "%s\n", line.c_str());
  };
  say("building training points: " + std::to_string(s.listing.train.views.size()) + " views x " +
      std::to_string(o.points_per_view) + " pixels, " + std::to_string(o.net.inputs()) + " " + o.net.features +
      " features each, in files in " + o.out_dir);
  const auto t_build = std::chrono::steady_clock::now();
  NnaoPoints p;
  StandardizerSums sums(o.net.inputs());
  p.train = build_points(s.listing.train.views, o, o.points_per_view, 1, "train-points", &sums, p.share, *d.kept);
  p.test = build_points(s.listing.test.views, o, o.test_points_per_view, 2, "test-points", nullptr, p.share, *d.kept);
  p.valid = build_points(s.validation.views, o, o.test_points_per_view, 3, "val-points", nullptr, p.share, *d.kept);
  p.views = int64_t(s.listing.train.views.size() + s.listing.test.views.size() + s.validation.views.size());
  if (runs::size() > 1)
    say("rank " + std::to_string(runs::rank()) + " built " + std::to_string(p.share.views_built) + " of " +
        std::to_string(p.views) + " views' points; " + std::to_string(p.share.exchange_seconds) +
        " s in the exchange (waiting for the other ranks included)");
  p.standardizer = sums.finish();
  standardize_file(p.train, p.standardizer);
  standardize_file(p.test, p.standardizer);
  standardize_file(p.valid, p.standardizer);
  copy_standardizer(net, p.standardizer);
  p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_build).count();
  return p;
}

// train-nnao's part of the training loop (runs/training_loop.h): a step is a batch of
// points from the chunked shuffle through the fused MLP step; an epoch ends with the test
// (and validation) MSE, the log and the chart; the output is nnao.blob.
class NnaoTask : public runs::TrainingTask {
 public:
  NnaoTask(const TrainOptions& o, NnaoModel& m, const NnaoPoints& p, runs::TrainingRun& run)
      : o_(o),
        m_(m),
        p_(p),
        run_(run),
        F_(p.train.features),
        B_(o.batch),
        mb_(o.batch / o.accumulate),
        order_(p.train.rows, o.shuffle_chunk, shuffle_buffer_rows(o)),
        params_(m.net.parameters()),
        fast_(m.net, o.batch / o.accumulate),
        xb_(size_t(B_ * F_)),
        yb_(size_t(B_)),
        threads_(num_threads()),
        blob_path_(run.path("nnao.blob")) {
    m_.net.train();
  }
  int64_t steps_per_epoch() const { return p_.train.count() / B_; }  // full batches only

  std::vector<Var<float>> trained_parameters() override { return params_; }
  std::vector<Rng*> rngs() override {
    std::vector<Rng*> r;
    for (auto& [name, g] : m_.net.named_rngs()) r.push_back(g);
    return r;
  }

  void begin_epoch(int64_t) override {
    order_.start_epoch(m_.data_rng);
    loss_sum_ = 0;
    // The step is ~20 us of work: waking a second core for it costs more than it saves
    // (the results are the same either way), so the steps run on one thread.
    set_num_threads(1);
    t_steps_ = std::chrono::steady_clock::now();
  }
  void begin_step(int64_t) override {
    for (int64_t b = 0; b < B_; ++b) {
      const char* row = order_.next(m_.data_rng);
      to_float(row_features(row), xb_.data() + b * F_, F_);
      yb_[size_t(b)] = row_target(row, F_);
    }
  }
  runs::StepValues step(int64_t) override {
    for (auto& prm : params_) prm.grad_buffer().zero();
    const float loss = fast_.forward_backward(xb_.data(), yb_.data(), float(o_.gamma));
    update(loss);
    return {loss};
  }
  runs::StepValues micro_batch(int64_t, int m, const runs::MicroRange&) override {
    for (auto& prm : params_) prm.grad_buffer().zero();
    return {fast_.forward_backward(xb_.data() + m * mb_ * F_, yb_.data() + m * mb_, float(o_.gamma))};
  }
  void apply(const runs::StepValues& mean) override { update(float(mean[0])); }
  std::string end_step(int64_t epoch, int64_t s, const runs::StepValues& v) override {
    loss_sum_ += float(v[0]);
    ++m_.step;
    if (s % 256 != 0 && s + 1 != steps_per_epoch()) return "";
    char status[80];
    std::snprintf(status, sizeof status, "epoch %lld loss %.4f", (long long)epoch + 1, loss_sum_ / double(s + 1));
    return status;
  }
  void end_epoch(int64_t epochs_done) override {
    step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_steps_).count();
    set_num_threads(threads_);
    timed_steps += steps_per_epoch();
    train_loss = loss_sum_ / double(steps_per_epoch());
    test_mse = evaluate_mse(m_.net, p_.test, p_.standardizer.target_std);
    runs::check_finite(test_mse, m_.step, "test MSE");
    runs::MetricsRecord rec{m_.step, epochs_done, {{"train_loss", train_loss}, {"test_mse", test_mse}}};
    if (p_.valid.count())
      rec.values.emplace_back("val_mse", val_mse = evaluate_mse(m_.net, p_.valid, p_.standardizer.target_std));
    run_.log(rec);
    if (run_.writes_files()) write_loss_chart(run_);
  }
  void write_outputs() override { save_weights(blob_path_, m_.net, "nnao", blob_config(o_)); }
  void stopped() override { set_num_threads(threads_); }

  // NaN until an epoch has run.
  double train_loss = std::nan(""), test_mse = std::nan(""), val_mse = std::nan("");
  double step_seconds = 0;  // the steps alone (no test pass)
  int64_t timed_steps = 0;

 private:
  // A NaN or Inf loss (a diverging learning rate, a NaN that slipped into the data) stops
  // the run before Adam touches the weights; one isfinite per ~20 us step.
  void update(float loss) {
    runs::check_finite(double(loss), m_.step + 1, "training loss");
    m_.opt.step();
  }

  const TrainOptions& o_;
  NnaoModel& m_;
  const NnaoPoints& p_;
  runs::TrainingRun& run_;
  const int64_t F_, B_, mb_;
  runs::ShuffledRows order_;
  std::vector<Var<float>> params_;
  nnao::NnaoFastStep fast_;
  std::vector<float> xb_, yb_;
  const int threads_;
  const std::string blob_path_;
  double loss_sum_ = 0;
  std::chrono::steady_clock::time_point t_steps_;
};

// The result, summary.json and the report.
inline TrainResult finish_run(runs::TrainingLoop& loop, const NnaoTask& task, const NnaoPoints& p,
                              const runs::LoopResult& lr, int64_t steps,
                              std::chrono::steady_clock::time_point t_start) {
  namespace fs = std::filesystem;
  runs::TrainingRun& run = loop.run();
  TrainResult res;
  res.build_seconds = p.seconds;
  res.train_points = p.train.count();
  res.test_points = p.test.count();
  res.train_loss = task.train_loss;
  res.test_mse = task.test_mse;
  res.val_mse = task.val_mse;
  if (!run.metrics().records().empty()) res.test_mse = run.metrics().records().back().get("test_mse");
  res.steps = steps;
  res.step_microseconds = task.timed_steps ? 1e6 * task.step_seconds / double(task.timed_steps) : 0;
  res.epoch_seconds = lr.epochs_run ? lr.epoch_seconds / double(lr.epochs_run) : 0;
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  res.stop_message = lr.stop_message;
  std::vector<std::pair<std::string, double>> figures = {{"train_points", double(res.train_points)},
                                                         {"test_points", double(res.test_points)},
                                                         {"test_mse", res.test_mse},
                                                         {"step_microseconds", res.step_microseconds},
                                                         {"build_seconds", res.build_seconds},
                                                         // The sharding of the build (about 1/N under mpirun -np N).
                                                         {"point_views", double(p.views)},
                                                         {"point_views_read_by_rank_0", double(p.share.views_built)},
                                                         {"epoch_seconds", res.epoch_seconds},
                                                         {"seconds", res.seconds}};
  res.exit_code = loop.finish(lr.stop_message, figures, [&](report::Report& r) {
    if (fs::exists(run.path("loss.svg"))) r.chart("loss.svg", "train loss per epoch");
    if (fs::exists(run.path("mse.svg"))) r.chart("mse.svg", "test (and validation) MSE per epoch");
  });
  return res;
}

inline TrainResult train_nnao(const TrainOptions& o) {
  const auto t_start = std::chrono::steady_clock::now();
  check_options(o);
  NnaoData data = open_data(o);
  NnaoModel model(o);
  runs::TrainingLoop loop(run_spec(o, data.splits.listing), model.ck, model.step, o.precision, o.quiet);
  const NnaoPoints points = build_all_points(o, data, model.net);
  data.kept.reset();
  if (points.train.count() < o.batch) throw std::runtime_error("fewer training points than one batch");
  NnaoTask task(o, model, points, loop.run());
  const runs::LoopResult r = loop.train(task, {.progress_label = "train-nnao",
                                               .epochs = o.epochs,
                                               .steps_per_epoch = task.steps_per_epoch(),
                                               .accumulate = o.accumulate,
                                               .bucket_mb = o.bucket_mb});
  return finish_run(loop, task, points, r, model.step, t_start);
}

}  // namespace nns::runs
