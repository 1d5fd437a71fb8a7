#pragma once
// The free parameters of every classical method in one value, the named handles that
// tune-classical-ao moves, and the text file that carries them to eval-ao:
//
//   # comment
//   HBAO.angle_bias 0.1
//   GTAO.falloff 0.615
//
// one "<method>.<parameter> <value>" per line; a parameter not in the file keeps its
// default (the values the methods used before they had parameters).
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "classical_ao/methods.h"
#include "core/atomic_file.h"

namespace nns::classical_ao {

using screen_space::GBuffer;

struct ClassicalParams {
  SsaoParams ssao;
  SsaoPlusParams ssao_plus;
  HbaoParams hbao;
  AlchemyParams alchemy;
  GtaoParams gtao;
};

// A parameter as the tuner sees it: its value and the interval it may take.
struct Tunable {
  std::string method, name;
  float* value;
  float lo, hi;
};

// Every method's parameters, in file order. The intervals bound the search, wide enough
// that the tuned values of the default data sit inside them.
inline std::vector<Tunable> tunables(ClassicalParams& p) {
  return {
      {"SSAO", "radius_scale", &p.ssao.radius_scale, 0.25f, 4},
      {"SSAO", "range", &p.ssao.range, 0.1f, 8},
      {"SSAO", "gain", &p.ssao.gain, 1, 4},
      {"SSAO+", "radius_scale", &p.ssao_plus.radius_scale, 0.25f, 4},
      {"SSAO+", "bias", &p.ssao_plus.bias, 0, 0.5f},
      {"HBAO", "radius_scale", &p.hbao.radius_scale, 0.25f, 4},
      {"HBAO", "angle_bias", &p.hbao.angle_bias, 0, 0.6f},
      {"Alchemy", "radius_scale", &p.alchemy.radius_scale, 0.25f, 4},
      {"Alchemy", "sigma", &p.alchemy.sigma, 0.02f, 3},
      {"Alchemy", "beta", &p.alchemy.beta, 0, 0.5f},
      {"Alchemy", "kappa", &p.alchemy.kappa, 0.25f, 4},
      {"GTAO", "radius_scale", &p.gtao.radius_scale, 0.25f, 4},
      {"GTAO", "falloff", &p.gtao.falloff, 0, 1},
      {"GTAO", "distribution", &p.gtao.distribution, 0.5f, 4},
      {"GTAO", "thickness", &p.gtao.thickness, 0, 4},
  };
}

inline std::vector<Tunable> tunables(ClassicalParams& p, const std::string& method) {
  std::vector<Tunable> out;
  for (auto& t : tunables(p))
    if (t.method == method) out.push_back(t);
  return out;
}

// The method `name` with parameters p (the vectorised form, or its scalar reference).
inline void run_classical(const std::string& name, const ClassicalParams& p, const GBuffer& g, int samples, float* out,
                          bool reference = false) {
  if (name == "SSAO") (reference ? ssao_reference_with : ssao_with)(g, samples, out, p.ssao);
  else if (name == "SSAO+") (reference ? ssao_plus_reference_with : ssao_plus_with)(g, samples, out, p.ssao_plus);
  else if (name == "HBAO") (reference ? hbao_reference_with : hbao_with)(g, samples, out, p.hbao);
  else if (name == "Alchemy") (reference ? alchemy_ao_reference_with : alchemy_ao_with)(g, samples, out, p.alchemy);
  else if (name == "GTAO") (reference ? gtao_reference_with : gtao_with)(g, samples, out, p.gtao);
  else classical_method(name);  // throws, naming the known methods
}

inline std::string format_classical_params(const ClassicalParams& p, const std::string& header = "") {
  std::ostringstream s;
  if (!header.empty()) s << "# " << header << "\n";
  ClassicalParams q = p;
  for (auto& t : tunables(q)) {
    char v[32];
    std::snprintf(v, sizeof v, "%.9g", double(*t.value));  // round-trips a float exactly
    s << t.method << "." << t.name << " " << v << "\n";
  }
  return s.str();
}

// A parameter file holds a line per parameter; anything near this size is no such file.
inline constexpr uint64_t kMaxClassicalParamsBytes = uint64_t(1) << 20;

// Errors name the file and line: unknown parameters, unreadable values, values outside
// the parameter's interval. A file that cannot be read (a FIFO, a device, one above the
// limit) is an error too, never the built-in parameters in its place.
inline ClassicalParams read_classical_params(const std::string& path) {
  std::istringstream f(read_file(path, kMaxClassicalParamsBytes));
  ClassicalParams p;
  auto ts = tunables(p);
  std::string line;
  for (int ln = 1; std::getline(f, line); ++ln) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream is(line);
    std::string key, extra;
    if (!(is >> key)) continue;
    const std::string where = path + ":" + std::to_string(ln) + ": ";
    double v;
    if (!(is >> v) || (is >> extra)) throw std::runtime_error(where + "expected '<method>.<parameter> <number>'");
    Tunable* t = nullptr;
    for (auto& c : ts)
      if (c.method + "." + c.name == key) t = &c;
    if (!t) throw std::runtime_error(where + "unknown parameter '" + key + "'");
    // Checked as stored (a float): a bound written back with 9 digits ("0.600000024" for
    // 0.6f) reads above the double bound, and a file this function wrote was refused
    // (found by fuzz_classical_params).
    const float f = float(v);
    if (!(f >= float(t->lo) && f <= float(t->hi)))
      throw std::runtime_error(where + key + " = " + std::to_string(v) + " is outside [" + std::to_string(t->lo) +
                               ", " + std::to_string(t->hi) + "]");
    *t->value = f;
  }
  return p;
}

}  // namespace nns::classical_ao
