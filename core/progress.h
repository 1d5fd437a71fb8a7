#pragma once
// A terminal progress bar with rate and ETA, for every long job (training, rendering,
// evaluation). Redraws at most ten times a second; on a non-terminal (CI logs) it
// prints a line every 10% instead of carriage-return updates.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace nns {

class Progress {
 public:
  Progress(std::string label, int64_t total)
      : label_(std::move(label)), total_(total), start_(clock::now()), tty_(isatty(2)) {}

  // `status` is shown after the bar, e.g. "loss 0.0123".
  void update(int64_t done, const std::string& status = "") {
    done_ = done;
    auto now = clock::now();
    bool finished = done >= total_;
    if (tty_) {
      if (!finished && now - last_ < std::chrono::milliseconds(100)) return;
    } else {
      int decile = total_ > 0 ? int(10 * done / total_) : 10;
      if (!finished && decile == last_decile_) return;
      last_decile_ = decile;
    }
    last_ = now;
    draw(status, finished);
  }
  void finish(const std::string& status = "") {
    if (done_ < total_) update(total_, status);
  }
  double elapsed_seconds() const { return std::chrono::duration<double>(clock::now() - start_).count(); }

  static std::string format_seconds(double s) {
    char buf[32];
    if (s < 60) std::snprintf(buf, sizeof buf, "%.0fs", s);
    else if (s < 3600) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
    else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, int(s) % 3600 / 60);
    return buf;
  }

 private:
  using clock = std::chrono::steady_clock;
  void draw(const std::string& status, bool finished) {
    double el = elapsed_seconds();
    double frac = total_ > 0 ? double(done_) / double(total_) : 1.0;
    double eta = frac > 0 ? el / frac - el : 0;
    const int width = 30;
    int filled = int(frac * width);
    std::string bar(size_t(filled), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "%s%s [%s] %3.0f%% %lld/%lld %s %s %s%s", tty_ ? "\r" : "", label_.c_str(), bar.c_str(),
                 100 * frac, (long long)done_, (long long)total_, format_seconds(el).c_str(),
                 finished ? "done" : ("ETA " + format_seconds(eta)).c_str(), status.c_str(),
                 tty_ && !finished ? "\033[K" : "\n");
    std::fflush(stderr);
  }

  std::string label_;
  int64_t total_, done_ = 0;
  clock::time_point start_, last_{};
  int last_decile_ = -1;
  bool tty_;
};

}  // namespace nns
