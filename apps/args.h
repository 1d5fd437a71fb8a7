#pragma once
// Command-line flags for every nnshade command: `--name value` or `--name=value`,
// `--help` prints the generated usage. Unknown flags and malformed values are errors
// that name the flag (exit 2), never a silent default.
//
//   nns::cli::Args args(argc, argv, "train-nnao", "Train NNAO on an EXR dataset.");
//   int epochs = args.get_int("--epochs", 100, "training epochs");
//   bool resume = args.get_flag("--resume", "continue from the last checkpoint");
//   args.done();  // handles --help and reports every problem found
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace nns::cli {

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
  // Every occurrence of a repeatable flag (e.g. --scene a.obj --scene b.obj).
  std::vector<std::string> get_list(const std::string& name, const std::string& help) {
    add_usage(name, "S ...", "", help + " (repeatable)");
    known_.insert(name);
    auto it = values_.find(name);
    return it == values_.end() ? std::vector<std::string>{} : it->second;
  }
  int get_int(const std::string& name, int def, const std::string& help) {
    add_usage(name, "N", std::to_string(def), help);
    auto v = last(name);
    if (!v) return def;
    try {
      size_t pos;
      long r = std::stol(*v, &pos);
      if (pos != v->size()) throw std::exception();
      return int(r);
    } catch (...) {
      errors_.push_back(name + ": expected an integer, got '" + *v + "'");
      return def;
    }
  }
  double get_double(const std::string& name, double def, const std::string& help) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", def);
    add_usage(name, "X", buf, help);
    auto v = last(name);
    if (!v) return def;
    try {
      size_t pos;
      double r = std::stod(*v, &pos);
      // std::stod accepts "nan" and "inf": no flag of ours means either.
      if (pos != v->size() || !std::isfinite(r)) throw std::exception();
      return r;
    } catch (...) {
      errors_.push_back(name + ": expected a finite number, got '" + *v + "'");
      return def;
    }
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
  std::string get_choice(const std::string& name, const std::string& def,
                         const std::vector<std::string>& choices, const std::string& help) {
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
      std::printf("usage: %s [flags]%s\n%s\n\nflags:\n%s  --help              this text\n",
                  program_.c_str(), positional_usage.empty() ? "" : (" " + positional_usage).c_str(),
                  summary_.c_str(), usage_.c_str());
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
  const std::string* last(const std::string& name) {
    known_.insert(name);
    auto it = values_.find(name);
    return it == values_.end() || it->second.empty() ? nullptr : &it->second.back();
  }
  void add_usage(const std::string& name, const std::string& meta, const std::string& def,
                 const std::string& help) {
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

}  // namespace nns::cli
