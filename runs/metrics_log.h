#pragma once
// One metrics format for every run: OUT/metrics.jsonl, one JSON object per line,
//   {"step":1200,"epoch":3,"train_loss":0.0123,"test_mse":null}
// "step" and "epoch" first, then the run's own numbers in the order it gave them. A value
// that is not finite is written as null (JSON has no NaN), so a diverged run still leaves
// a file every JSON reader takes.
//
// On --resume the log keeps exactly the lines its checkpoint covers (step <= the
// checkpoint's step) and drops the rest, including a line a killed run left half
// written; the kept lines are rewritten atomically before anything is appended.
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/atomic_file.h"

namespace nns::runs {

struct MetricsRecord {
  int64_t step = 0, epoch = 0;
  std::vector<std::pair<std::string, double>> values;

  double get(const std::string& key) const {
    for (auto& [k, v] : values)
      if (k == key) return v;
    return std::nan("");
  }
};

// 9 significant digits: a float survives the round trip exactly.
inline std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// A JSON string literal: quotes, backslashes and control characters escaped.
inline std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += char(c);
    else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else out += char(c);
  }
  return out + "\"";
}

inline std::string format_metrics_line(const MetricsRecord& r) {
  std::string s = "{\"step\":" + std::to_string(r.step) + ",\"epoch\":" + std::to_string(r.epoch);
  for (auto& [k, v] : r.values) s += ",\"" + k + "\":" + json_number(v);
  return s + "}";
}

// The inverse of format_metrics_line, and strict: anything else (a torn line, text that
// is not this format) gives nullopt rather than a guess. Keys are plain identifiers.
inline std::optional<MetricsRecord> parse_metrics_line(const std::string& line) {
  size_t i = 0;
  auto expect = [&](char c) {
    if (i < line.size() && line[i] == c) return ++i, true;
    return false;
  };
  auto key = [&](std::string& out) {
    if (!expect('"')) return false;
    size_t start = i;
    while (i < line.size() && (std::isalnum((unsigned char)line[i]) || line[i] == '_')) ++i;
    out = line.substr(start, i - start);
    return !out.empty() && expect('"') && expect(':');
  };
  auto number = [&](double& out) {
    if (line.compare(i, 4, "null") == 0) return i += 4, out = std::nan(""), true;
    size_t start = i;
    while (i < line.size() && std::string_view("+-.0123456789eE").find(line[i]) != std::string_view::npos) ++i;
    if (i == start || i - start > 40) return false;
    char* end = nullptr;
    const std::string text = line.substr(start, i - start);
    out = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size() && std::isfinite(out);
  };
  MetricsRecord r;
  std::string k;
  double v = 0;
  if (!expect('{')) return std::nullopt;
  if (!key(k) || k != "step" || !number(v) || v != std::floor(v) || std::fabs(v) > 9e15) return std::nullopt;
  r.step = int64_t(v);
  if (!expect(',') || !key(k) || k != "epoch" || !number(v) || v != std::floor(v) || std::fabs(v) > 9e15)
    return std::nullopt;
  r.epoch = int64_t(v);
  while (expect(',')) {
    if (!key(k) || !number(v)) return std::nullopt;
    r.values.emplace_back(k, v);
  }
  if (!expect('}') || i != line.size()) return std::nullopt;
  return r;
}

// The largest metrics log read back: a line per logged step of about 100 bytes gives
// millions of steps.
inline constexpr uint64_t kMaxMetricsBytes = uint64_t(1) << 30;

// Every well-formed line of a metrics file (none if it does not exist). Anything else at
// that name (a FIFO, a device, a file above the limit) is an error naming it.
inline std::vector<MetricsRecord> read_metrics(const std::string& path) {
  std::vector<MetricsRecord> out;
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec)) && !ec) return out;
  std::istringstream in(read_file(path, kMaxMetricsBytes));
  std::string line;
  while (std::getline(in, line))
    if (auto r = parse_metrics_line(line)) out.push_back(*r);
  return out;
}

inline std::vector<double> metrics_series(const std::vector<MetricsRecord>& records, const std::string& key) {
  std::vector<double> s;
  for (auto& r : records) s.push_back(key == "step" ? double(r.step) : key == "epoch" ? double(r.epoch) : r.get(key));
  return s;
}

class MetricsLog {
 public:
  MetricsLog() = default;
  // keep_up_to_step < 0: a new run, the log starts empty. Otherwise the lines of an
  // earlier run up to that step are kept (a resumed run).
  MetricsLog(std::string path, int64_t keep_up_to_step) : path_(std::move(path)) {
    std::string kept;
    if (keep_up_to_step >= 0)
      for (auto& r : read_metrics(path_))
        if (r.step <= keep_up_to_step) records_.push_back(r), kept += format_metrics_line(r) + "\n";
    write_file_atomic(path_, kept);
  }

  // A log made without a path (an MPI rank other than 0) keeps its records in memory.
  void append(const MetricsRecord& r) {
    if (!path_.empty()) {
      std::ofstream out(path_, std::ios::app);
      out << format_metrics_line(r) << "\n";
      out.flush();
      if (!out) throw std::runtime_error("cannot append to '" + path_ + "' (disk full?)");
    }
    records_.push_back(r);
  }

  const std::vector<MetricsRecord>& records() const { return records_; }
  std::vector<double> series(const std::string& key) const { return metrics_series(records_, key); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<MetricsRecord> records_;
};

}  // namespace nns::runs
