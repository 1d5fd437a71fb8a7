#pragma once
// The classical methods by name, with the sample counts eval-ao runs them at.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "classical_ao/alchemy_ao.h"
#include "classical_ao/gtao.h"
#include "classical_ao/hbao.h"
#include "classical_ao/ssao.h"
#include "classical_ao/ssao_plus.h"

namespace nns::classical_ao {

using screen_space::GBuffer;

struct ClassicalMethod {
  std::string name;
  std::vector<int> sample_counts;
  std::function<void(const GBuffer&, int, float*)> run;        // out: W*H AO, sky = 1; vectorised
  std::function<void(const GBuffer&, int, float*)> reference;  // the scalar loop it matches
};

inline const std::vector<ClassicalMethod>& classical_methods() {
  static const std::vector<ClassicalMethod> m = {
      {"SSAO", {4, 8, 16, 32}, ssao, ssao_reference},     {"SSAO+", {4, 8, 16, 32}, ssao_plus, ssao_plus_reference},
      {"HBAO", {16, 32, 64}, hbao, hbao_reference},       {"Alchemy", {4, 8, 16, 32}, alchemy_ao, alchemy_ao_reference},
      {"GTAO", {4, 8, 16, 32, 64}, gtao, gtao_reference},
  };
  return m;
}

inline const ClassicalMethod& classical_method(const std::string& name) {
  for (auto& m : classical_methods())
    if (m.name == name) return m;
  throw std::invalid_argument("unknown AO method '" + name + "' (known: SSAO, SSAO+, HBAO, Alchemy, GTAO)");
}

}  // namespace nns::classical_ao
