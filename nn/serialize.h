#pragma once
// Saving and loading a Module tree by dotted name ("down.0.conv.weight") through a Blob
// (core/blob.h): parameters and buffers as tensors of the module's scalar type, each
// module-owned Rng as its four u64 state words.
//
// Loading is strict: a name the module has and the blob lacks, a name the blob has and
// the module lacks, or a shape that differs is an error naming the tensor and the file.
//
//   save_weights("nnao.blob", model, "nnao", {{"hidden", "4"}});
//   Blob b = load_weights("nnao.blob", model, "nnao");   // b.config() rebuilt the model
#include <map>
#include <set>
#include <string>

#include "core/blob.h"
#include "nn/module.h"

namespace nns {

// Adds every parameter, buffer and Rng of `m` to `b`, each name prefixed by `prefix`.
template <class T>
void put_module(Blob& b, Module<T>& m, const std::string& prefix = "") {
  for (auto& [name, p] : m.named_parameters()) b.put(prefix + name, p.value());
  for (auto& [name, t] : m.named_buffers()) b.put(prefix + name, *t);
  for (auto& [name, r] : m.named_rngs()) b.put(prefix + name, Shape{4}, r->state().data());
}

// Restores everything put_module() wrote under `prefix`, in place: the Vars the
// optimizer holds see the new values.
template <class T>
void get_module(const Blob& b, Module<T>& m, const std::string& prefix = "") {
  std::set<std::string> expected;
  for (auto& [name, p] : m.named_parameters()) {
    b.read(prefix + name, p.shape(), p.value().data());
    expected.insert(prefix + name);
  }
  for (auto& [name, t] : m.named_buffers()) {
    b.read(prefix + name, t->shape(), t->data());
    expected.insert(prefix + name);
  }
  for (auto& [name, r] : m.named_rngs()) {
    Rng::State s;
    b.read(prefix + name, Shape{4}, s.data());
    r->set_state(s);
    expected.insert(prefix + name);
  }
  for (auto& [name, t] : b.tensors())
    if (name.compare(0, prefix.size(), prefix) == 0 && !expected.count(name))
      throw b.error("tensor '" + name + "' does not belong to the model (unexpected name)");
}

// A weights file: the model's kind and config, then its tensors.
template <class T>
void save_weights(const std::string& path, Module<T>& m, const std::string& kind,
                  const std::map<std::string, std::string>& config = {}) {
  Blob b(kind);
  for (auto& [k, v] : config) b.set_config(k, v);
  put_module(b, m);
  b.save(path);
}

// Loads a weights file into `m` and returns the blob (for its kind and config). A
// non-empty `expected_kind` must match the blob's.
template <class T>
Blob load_weights(const std::string& path, Module<T>& m, const std::string& expected_kind = "") {
  Blob b = Blob::load(path);
  if (!expected_kind.empty() && b.kind() != expected_kind)
    throw b.error("holds a '" + b.kind() + "' model, expected '" + expected_kind + "'");
  get_module(b, m);
  return b;
}

}  // namespace nns
