#pragma once
// Command-line flags for every nnshade command: `--name value` or `--name=value`,
// `--help` prints the generated usage. Unknown flags, malformed values and values out
// of a flag's range are errors that name the flag and the range (exit 2), never a
// silent default: every numeric flag states its range here, where it is read.
//
//   nns::apps::Args args(argc, argv, "train-nnao", "Train NNAO on an EXR dataset.");
//   int epochs = args.get_int("--epochs", 100, "training epochs", 0, 100000);
//   bool resume = args.get_flag("--resume", "continue from the last checkpoint");
//   args.done();  // handles --help and reports every problem found
#include <algorithm>
#include <climits>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace nns::apps {

class Args {
 public:
  Args(int argc, char** argv, std::string program, std::string summary)
      : program_(std::move(program)), summary_(std::move(summary)) {
    for (int i = 1; i < argc; ++i) {
      std::string a = argv[i];
      if (a == "--help" || a == "-h") {
        help_ = true;
        continue;
      }
      if (a.rfind("--", 0) != 0) {
        positional_.push_back(a);
        continue;
      }
      auto eq = a.find('=');
      if (eq != std::string::npos) {
        values_[a.substr(0, eq)].push_back(a.substr(eq + 1));
      } else if (i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0) {
        values_[a].push_back(argv[++i]);
      } else {
        values_[a].push_back("");  // a bare flag
      }
    }
  }

  std::string get_string(const std::string& name, const std::string& def, const std::string& help) {
    add_usage(name, "S", def, help);
    auto v = last(name);
    return v ? *v : def;
  }
  // A file or folder: given, it must name one ("--out ''" wrote into the current folder).
  std::string get_path(const std::string& name, const std::string& def, const std::string& help) {
    const std::string v = get_string(name, def, help);
    if (last(name) && v.empty()) error(name + ": expected a path, got ''");
    return v;
  }
  // A comma-separated list of names ("cave,pipes,round"); empty items are dropped, and
  // a value that names nothing ("", ",") is an error: "--methods ''" ran nothing and
  // exited 0.
  std::vector<std::string> get_names(const std::string& name, const std::string& def, const std::string& help) {
    std::vector<std::string> out;
    const std::string text = get_string(name, def, help + " (comma-separated)");
    std::stringstream ss(text);
    for (std::string item; std::getline(ss, item, ',');)
      if (!item.empty()) out.push_back(item);
    if ((!text.empty() || last(name)) && out.empty()) error(name + ": no name in '" + text + "'");
    return out;
  }
  // Every occurrence of a repeatable flag (e.g. --scene a.obj --scene b.obj).
  std::vector<std::string> get_list(const std::string& name, const std::string& help) {
    add_usage(name, "S ...", "", help + " (repeatable)");
    known_.insert(name);
    auto it = values_.find(name);
    return it == values_.end() ? std::vector<std::string>{} : it->second;
  }
  // An integer in [lo, hi]. Parsed as 64-bit and range-checked before it becomes an
  // int, so 4294967297 is refused instead of wrapping to 1.
  int get_int(const std::string& name, int def, const std::string& help, long long lo = INT_MIN,
              long long hi = INT_MAX) {
    add_usage(name, "N", std::to_string(def) + range_text(double(lo), double(hi), INT_MIN, INT_MAX), help);
    auto v = last(name);
    if (!v) return def;
    long long r = 0;
    try {
      size_t pos;
      r = std::stoll(*v, &pos);
      if (pos != v->size()) throw std::exception();
    } catch (...) {
      errors_.push_back(name + ": expected an integer, got '" + *v + "'");
      return def;
    }
    if (r < lo || r > hi || r < INT_MIN || r > INT_MAX) {
      errors_.push_back(name + ": " + *v + " is out of range: expected an integer in " +
                        bounds(double(std::max<long long>(lo, INT_MIN)), double(std::min<long long>(hi, INT_MAX))));
      return def;
    }
    return int(r);
  }
  // A comma-separated list of integers, each in [lo, hi], e.g. --nnao-samples 16,64.
  std::vector<int> get_int_list(const std::string& name, const std::string& def, const std::string& help,
                                long long lo = INT_MIN, long long hi = INT_MAX) {
    add_usage(name, "N,N,...", def + range_text(double(lo), double(hi), INT_MIN, INT_MAX), help);
    auto v = last(name);
    const std::string text = v ? *v : def;
    std::vector<int> out;
    size_t start = 0;
    while (start <= text.size()) {
      size_t comma = text.find(',', start);
      if (comma == std::string::npos) comma = text.size();
      const std::string item = text.substr(start, comma - start);
      long long r = 0;
      size_t pos = 0;
      try {
        r = std::stoll(item, &pos);
      } catch (...) {
        pos = 0;
      }
      if (item.empty() || pos != item.size()) {
        errors_.push_back(name + ": expected a comma-separated list of integers, got '" + text + "'");
        return {};
      }
      if (r < lo || r > hi || r < INT_MIN || r > INT_MAX) {
        errors_.push_back(name + ": " + item + " is out of range: expected integers in " +
                          bounds(double(std::max<long long>(lo, INT_MIN)), double(std::min<long long>(hi, INT_MAX))));
        return {};
      }
      out.push_back(int(r));
      start = comma + 1;
    }
    return out;
  }
  // A finite number in [lo, hi]. Every real-valued flag ends up a float somewhere, so the
  // range never reaches past the largest float: 1e39 passed a check in double and became
  // inf (an infinite radius, every pixel sky).
  double get_double(const std::string& name, double def, const std::string& help, double lo = -HUGE_VAL,
                    double hi = HUGE_VAL) {
    lo = std::max(lo, -double(FLT_MAX));
    hi = std::min(hi, double(FLT_MAX));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", def);
    add_usage(name, "X", buf + range_text(lo, hi, -HUGE_VAL, HUGE_VAL), help);
    auto v = last(name);
    if (!v) return def;
    double r = 0;
    try {
      size_t pos;
      r = std::stod(*v, &pos);
      // std::stod accepts "nan" and "inf": no flag of ours means either.
      if (pos != v->size() || !std::isfinite(r)) throw std::exception();
    } catch (...) {
      errors_.push_back(name + ": expected a finite number, got '" + *v + "'");
      return def;
    }
    if (r < lo || r > hi || !std::isfinite(float(r))) {
      errors_.push_back(name + ": " + *v + " is out of range: expected a number in " + bounds(lo, hi));
      return def;
    }
    return r;
  }
  bool get_flag(const std::string& name, const std::string& help) {
    add_usage(name, "", "", help);
    auto v = last(name);
    if (!v) return false;
    if (v->empty() || *v == "on" || *v == "true" || *v == "1") return true;
    if (*v == "off" || *v == "false" || *v == "0") return false;
    errors_.push_back(name + ": expected no value or on/off, got '" + *v + "'");
    return false;
  }
  // A value from a fixed set, e.g. --mode front|surround.
  std::string get_choice(const std::string& name, const std::string& def, const std::vector<std::string>& choices,
                         const std::string& help) {
    std::string alts;
    for (auto& c : choices) alts += (alts.empty() ? "" : "|") + c;
    add_usage(name, alts, def, help);
    auto v = last(name);
    if (!v) return def;
    for (auto& c : choices)
      if (*v == c) return c;
    errors_.push_back(name + ": expected one of " + alts + ", got '" + *v + "'");
    return def;
  }
  // Records a problem found while interpreting flags (e.g. a range check).
  void error(const std::string& message) { errors_.push_back(message); }
  const std::vector<std::string>& positional() const { return positional_; }

  // Call after every get_*: prints usage for --help (exit 0); exits 2 on any problem.
  void done(const std::string& positional_usage = "") {
    if (help_) {
      std::printf("usage: %s [flags]%s\n%s\n\nflags:\n%s  --help              this text\n", program_.c_str(),
                  positional_usage.empty() ? "" : (" " + positional_usage).c_str(), summary_.c_str(), usage_.c_str());
      std::exit(0);
    }
    for (auto& [name, v] : values_)
      if (!known_.count(name)) errors_.push_back("unknown flag " + name);
    if (positional_usage.empty() && !positional_.empty())
      errors_.push_back("unexpected argument '" + positional_[0] + "'");
    if (!errors_.empty()) {
      for (auto& e : errors_) std::fprintf(stderr, "%s: error: %s\n", program_.c_str(), e.c_str());
      std::fprintf(stderr, "run '%s --help' for usage\n", program_.c_str());
      std::exit(2);
    }
  }

 private:
  // "[0, 100]", "[1, inf)", "(-inf, 5]"; a real-valued flag's open end is the largest
  // float, "[0, 3.40282e+38]".
  static std::string bounds(double lo, double hi) {
    std::string s = std::isinf(lo) ? std::string("(-inf") : "[" + num(lo);
    s += ", ";
    s += std::isinf(hi) ? std::string("inf)") : num(hi) + "]";
    return s;
  }
  static std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, std::fabs(v) == double(FLT_MAX) ? "%g" : "%.15g", v);
    return b;
  }
  // ", range [lo, hi]" for the usage line, or nothing when the flag has no range.
  static std::string range_text(double lo, double hi, double none_lo, double none_hi) {
    if (lo <= none_lo && hi >= none_hi) return "";
    return ", range " + bounds(lo <= none_lo ? -HUGE_VAL : lo, hi >= none_hi ? HUGE_VAL : hi);
  }
  const std::string* last(const std::string& name) {
    known_.insert(name);
    auto it = values_.find(name);
    return it == values_.end() || it->second.empty() ? nullptr : &it->second.back();
  }
  void add_usage(const std::string& name, const std::string& meta, const std::string& def, const std::string& help) {
    std::string left = "  " + name + (meta.empty() ? "" : " " + meta);
    if (left.size() < 22) left.resize(22, ' ');
    else left += "  ";
    usage_ += left + help + (def.empty() ? "" : " (default " + def + ")") + "\n";
  }

  std::string program_, summary_, usage_;
  std::map<std::string, std::vector<std::string>> values_;
  std::set<std::string> known_;
  std::vector<std::string> positional_, errors_;
  bool help_ = false;
};

// Runs `body` and turns an exception into "program: error: what" and exit code 1.
inline int run_main(const char* program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return 1;
  }
}

}  // namespace nns::apps
