// The hostile-input sweep: every command (one per apps/*.cpp), every numeric, choice and
// list flag its --help lists, fed the values a hostile user tries first. A value outside
// what --help states must be refused before any work: exit 2, a message naming the flag,
// no signal, nothing in the output folder. A value --help allows may run (the inputs
// point at an empty folder or a missing file, so it fails fast), but never die of a
// signal or leave a temporary behind, and when it fails it leaves nothing. The flags are
// read from --help, so a new flag or a new command is swept without anyone writing a
// case for it.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/blob.h"
#include "fixtures/random_nnao_blob.h"
#include "models/gi/gi_model_io.h"

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kHostile = {
    "-1", "0", "nan", "inf", "-inf", "1e39", "1e309", "4294967297", "9223372036854775808", "", "abc", ","};

struct Flag {
  std::string name, meta;  // meta: N, X, N,N,..., a|b|c, or S (comma-separated names)
  bool names = false;      // a comma-separated list of names
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  std::vector<std::string> choices;
};

struct Command {
  std::string name, path, positional;  // positional: the usage line's arguments after [flags]
  std::vector<Flag> flags;
  std::vector<std::string> all_flags;  // every flag, for the inputs
};

struct Outcome {
  bool started = false, signalled = false, timed_out = false;
  int code = -1, signal = 0;
  std::string output;
};

// Runs argv with stdout and stderr captured, in `cwd`; kills it after `timeout`.
Outcome run(const std::vector<std::string>& argv, const std::string& cwd, double timeout) {
  Outcome r;
  const std::string log = cwd + "/.output";
  // Built before the fork: the child of a threaded process may not allocate.
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = ::fork();
  if (pid < 0) return r;
  if (pid == 0) {
    ::setpgid(0, 0);
    if (::chdir(cwd.c_str()) != 0) ::_exit(127);
    int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) ::_exit(127);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    int null = ::open("/dev/null", O_RDONLY);
    ::dup2(null, 0);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  r.started = true;
  const auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  for (;;) {
    pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout) {
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      r.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (!r.timed_out && WIFSIGNALED(status)) r.signalled = true, r.signal = WTERMSIG(status);
  if (WIFEXITED(status)) r.code = WEXITSTATUS(status);
  std::ifstream in(log);
  r.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  fs::remove(log);
  return r;
}

// "[0, 100]", "[1, inf)", "(-inf, 5]" as apps/args.h writes them.
bool parse_bounds(const std::string& s, double& lo, double& hi) {
  const auto comma = s.find(", ");
  if (s.size() < 5 || comma == std::string::npos) return false;
  const std::string a = s.substr(1, comma - 1), b = s.substr(comma + 2, s.size() - comma - 3);
  lo = a == "-inf" ? -HUGE_VAL : std::strtod(a.c_str(), nullptr);
  hi = b == "inf" ? HUGE_VAL : std::strtod(b.c_str(), nullptr);
  return true;
}

Command read_help(const std::string& name, const std::string& path, const std::string& cwd) {
  Command c;
  c.name = name, c.path = path;
  Outcome h = run({path, "--help"}, cwd, 20);
  EXPECT_EQ(h.code, 0) << name << " --help\n" << h.output;
  std::istringstream in(h.output);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("usage: ", 0) == 0) {
      const auto at = line.find("[flags]");
      if (at != std::string::npos) c.positional = line.substr(at + 7);
      continue;
    }
    if (line.rfind("  --", 0) != 0) continue;
    Flag f;
    const auto name_end = line.find(' ', 2);
    f.name = line.substr(2, name_end - 2);
    c.all_flags.push_back(f.name);
    if (f.name == "--help") continue;
    // "--name META help": apps/args.h pads the name and meta to 22 columns, so one space
    // may end the meta as well as the name; a meta is one of args.h's few forms.
    if (name_end + 1 < line.size() && line[name_end + 1] != ' ') {
      const auto token_end = std::min(line.find(' ', name_end + 1), line.size());
      const std::string token = line.substr(name_end + 1, token_end - name_end - 1);
      if (token == "N" || token == "X" || token == "S" || token == "N,N,..." || token.find('|') != std::string::npos)
        f.meta = token;
      if (token == "S" && line.compare(token_end, 4, " ...") == 0) f.meta = "S ...";
    }
    const std::string help = line.substr(name_end);
    if (f.meta == "S") {
      if (help.find("(comma-separated)") == std::string::npos) continue;  // a path or a name
      f.names = true;
    } else if (f.meta.empty() || f.meta == "S ...") {
      continue;  // on/off flags, repeatable paths
    } else if (f.meta != "N" && f.meta != "X" && f.meta != "N,N,...") {
      std::stringstream ss(f.meta);
      for (std::string ch; std::getline(ss, ch, '|');) f.choices.push_back(ch);
    }
    const auto range = help.rfind(", range ");
    if (range != std::string::npos) {
      const auto end = help.find_first_of("])", range + 9);
      EXPECT_TRUE(parse_bounds(help.substr(range + 8, end - range - 7), f.lo, f.hi)) << name << ": " << line;
    }
    if ((f.meta == "N" || f.meta == "N,N,...") && range == std::string::npos) f.lo = INT_MIN, f.hi = INT_MAX;
    c.flags.push_back(f);
  }
  return c;
}

bool full_integer(const std::string& v, long long& out) {
  if (v.empty()) return false;
  errno = 0;
  char* end = nullptr;
  out = std::strtoll(v.c_str(), &end, 10);
  return errno == 0 && *end == '\0' && !std::isspace(static_cast<unsigned char>(v[0]));
}

// Does --help allow `v` for `f`?
bool allowed(const Flag& f, const std::string& v) {
  if (f.names) {
    for (char ch : v)
      if (ch != ',') return true;
    return false;  // "" and "," name nothing
  }
  if (!f.choices.empty()) {
    for (auto& ch : f.choices)
      if (ch == v) return true;
    return false;
  }
  auto integer_ok = [&](const std::string& item) {
    long long n;
    return full_integer(item, n) && double(n) >= f.lo && double(n) <= f.hi && n >= INT_MIN && n <= INT_MAX;
  };
  if (f.meta == "N") return integer_ok(v);
  if (f.meta == "N,N,...") {
    size_t start = 0;
    for (;;) {
      const size_t comma = std::min(v.find(',', start), v.size());
      if (!integer_ok(v.substr(start, comma - start))) return false;
      if (comma == v.size()) return true;
      start = comma + 1;
    }
  }
  // X: a finite number in the stated range, finite as a float too.
  if (v.empty() || std::isspace(static_cast<unsigned char>(v[0]))) return false;
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  return errno == 0 && *end == '\0' && std::isfinite(x) && std::isfinite(float(x)) && x >= f.lo && x <= f.hi;
}

std::vector<std::string> leftovers(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return out;
  for (auto& e : fs::recursive_directory_iterator(dir, ec)) out.push_back(e.path().string());
  return out;
}

std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (auto& p : leftovers(dir))
    if (p.find(".tmp.") != std::string::npos || p.find(".partial-") != std::string::npos) out.push_back(p);
  return out;
}

// A run: one command and flag-value pairs. Every value --help allows runs alone (it
// may do work, and must not crash); the values it does not allow are refused by the one
// flag parser, which reports every problem before it exits, so a command takes them all
// at once, one run per value: each flag must be named in that run's errors. A process
// start of a command linked with OpenImageIO costs about 0.2 s of CPU (260 shared
// libraries), so the ~1600 cases as single runs were 3 minutes.
struct Case {
  const Command* command;
  std::vector<const Flag*> flags;
  std::string value;
  bool allowed;
  Outcome outcome;
  std::vector<std::string> temporaries, written;
};

std::vector<Case> plan_runs(const std::vector<Command>& commands, size_t& pairs) {
  std::vector<Case> runs;
  for (const Command& c : commands)
    for (const std::string& v : kHostile) {
      Case refused{&c, {}, v, false, {}, {}, {}};
      for (const Flag& f : c.flags) {
        ++pairs;
        if (allowed(f, v)) runs.push_back({&c, {&f}, v, true, {}, {}, {}});
        else refused.flags.push_back(&f);
      }
      if (!refused.flags.empty()) runs.push_back(refused);
    }
  return runs;
}

// Runs the case in `mine`/out and `mine`/cwd, given inputs that make an allowed value
// fail fast instead of training or rendering, and records what it left behind.
void run_case(Case& k, const fs::path& mine, const std::string& empty, const std::string& missing) {
  const fs::path out = mine / "out", cwd = mine / "cwd";
  const Command& c = *k.command;
  std::vector<std::string> argv = {c.path};
  for (auto& f : c.all_flags) {
    if (f == "--data") argv.insert(argv.end(), {f, empty});
    if (f == "--model" || f == "--in" || f == "--scene") argv.insert(argv.end(), {f, missing});
    if (f == "--out") argv.insert(argv.end(), {f, (out / "o").string()});
  }
  if (!c.positional.empty()) argv.push_back(empty);
  for (const Flag* f : k.flags) argv.insert(argv.end(), {f->name, k.value});
  std::error_code ec;
  fs::remove_all(out, ec);
  fs::remove_all(cwd, ec);
  fs::create_directories(cwd);
  k.outcome = run(argv, cwd.string(), k.allowed ? 5 : 20);
  k.temporaries = temporaries(out);
  for (auto& t : temporaries(cwd)) k.temporaries.push_back(t);
  k.written = leftovers(out);
  for (auto& t : leftovers(cwd)) k.written.push_back(t);
}

void check_case(const Case& k) {
  const Outcome& r = k.outcome;
  std::string names;
  for (const Flag* f : k.flags) names += (names.empty() ? "" : " ") + f->name;
  const std::string what =
      k.command->name + " " + names + " '" + k.value + "' (" + (k.allowed ? "allowed" : "not allowed") + " by --help)";
  EXPECT_TRUE(r.started) << what;
  EXPECT_FALSE(r.signalled) << what << ": killed by signal " << r.signal << "\n" << r.output;
  // A run the harness stopped with SIGKILL may leave a temporary (the next run into the
  // folder removes it); one that ended by itself may not.
  if (!r.timed_out) EXPECT_TRUE(k.temporaries.empty()) << what << ": left " << k.temporaries.front();
  // A run that failed by itself (its inputs are an empty folder or a missing file) leaves
  // nothing, not even the output folder it made.
  if (!r.timed_out && r.code != 0) EXPECT_TRUE(k.written.empty()) << what << ": left " << k.written.front();
  if (k.allowed) return;  // it may run; it failed fast or was stopped, and did not crash
  EXPECT_FALSE(r.timed_out) << what << ": still running after 20 s";
  EXPECT_EQ(r.code, 2) << what << "\n" << r.output;
  for (const Flag* f : k.flags)
    EXPECT_NE(r.output.find("error: " + f->name), std::string::npos)
        << k.command->name << " " << f->name << " '" << k.value << "': the flag is not named\n"
        << r.output;
  EXPECT_TRUE(k.written.empty()) << what << ": wrote " << k.written.front();
}

TEST(HostileFlags, EveryFlagOfEveryCommandRefusesWhatItsHelpDoesNotAllow) {
  const fs::path bin = fs::path(NNSHADE_BINARY_DIR) / "bin";
  const fs::path work_root = fs::temp_directory_path() / ("nns_hostile_flags_" + std::to_string(::getpid()));
  fs::remove_all(work_root);
  fs::create_directories(work_root / "empty");
  fs::create_directories(work_root / "cwd");
  const std::string empty = (work_root / "empty").string(), missing = (work_root / "missing.file").string();

  std::vector<Command> commands;
  for (auto& e : fs::directory_iterator(fs::path(NNSHADE_SOURCE_DIR) / "apps"))
    if (e.path().extension() == ".cpp") {
      const std::string name = e.path().stem().string();
      ASSERT_TRUE(fs::exists(bin / name)) << "command " << name << " is not built";
      commands.push_back(read_help(name, (bin / name).string(), (work_root / "cwd").string()));
    }
  std::sort(commands.begin(), commands.end(), [](auto& a, auto& b) { return a.name < b.name; });
  ASSERT_GE(commands.size(), 10u);

  size_t pairs = 0;
  std::vector<Case> runs = plan_runs(commands, pairs);
  const unsigned workers = std::max(2u, std::min(8u, std::thread::hardware_concurrency()));
  std::atomic<size_t> next{0};
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (unsigned w = 0; w < workers; ++w)
    pool.emplace_back([&, w] {
      for (size_t i; (i = next.fetch_add(1)) < runs.size();)
        run_case(runs[i], work_root / ("w" + std::to_string(w)), empty, missing);
    });
  for (auto& t : pool) t.join();

  for (const Case& k : runs) check_case(k);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("hostile flags: %zu cases (flag and value) over %zu commands in %zu runs, %.1f s (%u at a time)\n", pairs,
              commands.size(), runs.size(), seconds, workers);
  RecordProperty("cases", int(pairs));
  fs::remove_all(work_root);
}

// `b` with the first value of its first f32 tensor set to `v` (CRC and all valid).
nns::Blob poisoned(const nns::Blob& b, float v) {
  nns::Blob out(b.kind());
  for (auto& [k, val] : b.config()) out.set_config(k, val);
  bool first = true;
  for (auto& [n, t] : b.tensors()) {
    const nns::Shape sh(t.dims.begin(), t.dims.end());
    if (t.dtype == nns::DType::F32) {
      std::vector<float> x(size_t(t.numel()));
      std::memcpy(x.data(), t.bytes.data(), t.bytes.size());
      if (first && !x.empty()) x[0] = v, first = false;
      out.put(n, sh, x.data());
    } else if (t.dtype == nns::DType::F64) {
      out.put(n, sh, reinterpret_cast<const double*>(t.bytes.data()));
    } else if (t.dtype == nns::DType::U64) {
      out.put(n, sh, reinterpret_cast<const uint64_t*>(t.bytes.data()));
    } else {
      out.put(n, sh, reinterpret_cast<const int64_t*>(t.bytes.data()));
    }
  }
  return out;
}

// The corruptions a CRC does not catch, and files that are no files, against every
// command that reads a model before anything else: refused (non-zero exit) naming the
// file, at once, without a signal and without output.
TEST(HostileFlags, EveryModelReaderRefusesAPoisonedOrEndlessModelNamingIt) {
  const fs::path work = fs::temp_directory_path() / ("nns_hostile_models_" + std::to_string(::getpid()));
  fs::remove_all(work);
  fs::create_directories(work / "cwd");
  std::vector<std::string> models;
  auto save = [&](const nns::Blob& b, const std::string& name) {
    b.save((work / name).string());
    models.push_back((work / name).string());
  };
  const nns::Blob nnao = nns::fixtures::random_nnao_blob(3, 4, 1);
  save(poisoned(nnao, std::nanf("")), "nnao-nan.blob");
  save(poisoned(nnao, HUGE_VALF), "nnao-inf.blob");
  nns::Blob wide = nnao;
  wide.set_config("window", std::string("4294967299"));  // 3 after a 32-bit narrowing
  save(wide, "nnao-huge-window.blob");
  nns::gi::GeneratorConfig gc;
  nns::gi::GiInputConfig in;
  in.size = 16;
  gc.unet.in_channels = in.channels(), gc.unet.ngf = 2, gc.unet.levels = 2, gc.unet.dropout_blocks = 1;
  nns::Rng rng(1);
  auto G = nns::gi::make_generator<float>(gc, rng);
  nns::gi::save_generator_blob((work / "G.blob").string(), *G, in, gc, "gan");
  const nns::Blob gi = nns::Blob::load((work / "G.blob").string());
  save(poisoned(gi, std::nanf("")), "gi-nan.blob");
  nns::Blob big = gi;
  big.set_config("size", std::string("4294967312"));  // 16 after a 32-bit narrowing
  save(big, "gi-huge-size.blob");
  const std::string fifo = (work / "fifo.blob").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  models.push_back(fifo);
  models.push_back("/dev/zero");
  fs::create_directories(work / "folder.blob");
  models.push_back((work / "folder.blob").string());

  const fs::path bin = fs::path(NNSHADE_BINARY_DIR) / "bin";
  const fs::path out = work / "out";
  int cases = 0;
  for (const char* app : {"nnao-infer", "export-nnao", "gi-infer"})
    for (const std::string& model : models) {
      ++cases;
      fs::remove_all(out);
      std::vector<std::string> argv = {(bin / app).string(), "--model", model, "--out", (out / "o.exr").string()};
      if (std::string(app) != "export-nnao") argv.insert(argv.end(), {"--in", (work / "missing.exr").string()});
      const Outcome r = run(argv, (work / "cwd").string(), 20);
      const std::string what = std::string(app) + " --model " + model;
      EXPECT_FALSE(r.timed_out) << what << ": still reading after 20 s";
      EXPECT_FALSE(r.signalled) << what << ": killed by signal " << r.signal << "\n" << r.output;
      EXPECT_NE(r.code, 0) << what << "\n" << r.output;
      EXPECT_NE(r.output.find(model), std::string::npos) << what << ": the file is not named\n" << r.output;
      EXPECT_TRUE(leftovers(out).empty()) << what << ": wrote " << leftovers(out).front();
    }
  std::printf("hostile models: %d cases\n", cases);
  fs::remove_all(work);
}

// The evaluators make their output folder before they read the model and the views: a
// model that is no blob, or a folder without views, used to leave that folder behind
// with the lock file (and eval-gi's empty previews/) in it.
TEST(HostileFlags, AnEvaluatorRefusingItsInputsLeavesNoOutputFolder) {
  const fs::path work = fs::temp_directory_path() / ("nns_hostile_eval_" + std::to_string(::getpid()));
  fs::remove_all(work);
  fs::create_directories(work / "cwd");
  fs::create_directories(work / "empty");
  const std::string junk = (work / "junk.blob").string(), empty = (work / "empty").string();
  std::ofstream(junk) << "no blob";
  const fs::path bin = fs::path(NNSHADE_BINARY_DIR) / "bin";
  const fs::path out = work / "out";
  const std::vector<std::vector<std::string>> runs = {
      {"eval-gi", "--data", empty, "--model", junk},
      {"eval-ao", "--data", empty, "--model", junk},
      {"eval-ao", "--data", empty},
  };
  for (const auto& args : runs) {
    std::vector<std::string> argv = {(bin / args[0]).string()};
    argv.insert(argv.end(), args.begin() + 1, args.end());
    argv.insert(argv.end(), {"--out", out.string()});
    std::string what;
    for (const auto& a : args) what += a + " ";
    const Outcome r = run(argv, (work / "cwd").string(), 60);
    EXPECT_FALSE(r.signalled) << what << ": killed by signal " << r.signal << "\n" << r.output;
    EXPECT_EQ(r.code, 1) << what << "\n" << r.output;
    const bool named = r.output.find(junk) != std::string::npos || r.output.find(empty) != std::string::npos;
    EXPECT_TRUE(named) << what << ": the input is not named\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << what << ": left " << out;
    fs::remove_all(out);
  }
  fs::remove_all(work);
}

}  // namespace
