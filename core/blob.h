#pragma once
// Blob: the one file format for weights and checkpoints (specified byte by byte in
// docs/weights-format.md; tools/read_blob.py reads it with numpy alone).
//
// A blob holds a model kind ("nnao", "pix2pix-unet", ...), string key/values (the
// model's config, so a blob alone rebuilds its model) and named tensors with a dtype
// and a shape. Everything is little-endian; tensor data starts on a 64-byte boundary so
// an engine can map the file and use the floats in place; a CRC-32 of everything before
// it closes the file.
//
//   Blob b("nnao");
//   b.set_config("hidden", 4);
//   b.put("fc1.weight", w);                 // Tensor<float> -> f32
//   b.save("nnao.blob");                    // temp file + fsync + rename
//   Blob r = Blob::load("nnao.blob");       // throws std::runtime_error naming the file
//   Tensor<float> w2 = r.tensor<float>("fc1.weight", w.shape());
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/blob_crc32.h"
#include "core/atomic_file.h"
#include "core/kernels/finite.h"
#include "core/tensor.h"

static_assert(std::endian::native == std::endian::little,
              "blob I/O copies little-endian bytes directly; add byte swaps for this host");

namespace nns {

enum class DType : uint32_t { F32 = 1, F64 = 2, U64 = 3, I64 = 4 };

inline const char* dtype_name(DType d) {
  switch (d) {
    case DType::F32:
      return "f32";
    case DType::F64:
      return "f64";
    case DType::U64:
      return "u64";
    case DType::I64:
      return "i64";
  }
  return "unknown";
}
inline size_t dtype_size(DType d) { return d == DType::F32 ? 4 : 8; }
template <class T>
constexpr DType dtype_of();
template <>
constexpr DType dtype_of<float>() {
  return DType::F32;
}
template <>
constexpr DType dtype_of<double>() {
  return DType::F64;
}
template <>
constexpr DType dtype_of<uint64_t>() {
  return DType::U64;
}
template <>
constexpr DType dtype_of<int64_t>() {
  return DType::I64;
}

struct BlobTensor {
  DType dtype = DType::F32;
  std::vector<int64_t> dims;
  std::string bytes;  // numel * dtype_size little-endian values, row-major

  int64_t numel() const {
    int64_t n = 1;
    for (int64_t d : dims) n *= d;
    return n;
  }
  std::string shape_str() const { return Shape(dims.begin(), dims.end()).str(); }
};

class Blob {
 public:
  static constexpr char kMagic[8] = {'N', 'N', 'S', 'B', 'L', 'O', 'B', '\0'};
  static constexpr uint32_t kVersion = 1;
  static constexpr size_t kAlign = 64;
  static constexpr size_t kFixedHeader = 24;  // magic, version, flags, file size

  Blob() = default;
  explicit Blob(std::string kind) : kind_(std::move(kind)) {}

  const std::string& kind() const { return kind_; }
  void set_kind(std::string k) { kind_ = std::move(k); }
  // Where the blob came from ("<memory>" if built here): every error names it.
  const std::string& source() const { return source_; }

  // ---- config: string key/values, numbers written so they read back exactly ----
  const std::map<std::string, std::string>& config() const { return config_; }
  void set_config(const std::string& key, const std::string& value) { config_[key] = value; }
  void set_config(const std::string& key, const char* value) { config_[key] = value; }
  void set_config(const std::string& key, int64_t value) { config_[key] = std::to_string(value); }
  void set_config(const std::string& key, int value) { set_config(key, int64_t(value)); }
  void set_config(const std::string& key, double value) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", value);
    config_[key] = buf;
  }
  bool has_config(const std::string& key) const { return config_.count(key) != 0; }
  const std::string& config_string(const std::string& key) const {
    auto it = config_.find(key);
    if (it == config_.end()) throw error("config key '" + key + "' is missing");
    return it->second;
  }
  int64_t config_int(const std::string& key) const {
    const std::string& v = config_string(key);
    try {
      size_t pos;
      int64_t r = std::stoll(v, &pos);
      if (pos == v.size()) return r;
    } catch (...) {
    }
    throw error("config key '" + key + "' is '" + v + "', not an integer");
  }
  // An integer key checked as stored, before a caller narrows it: a window of
  // 4294967303 must not read as 7.
  int config_int(const std::string& key, int64_t lo, int64_t hi) const {
    const int64_t v = config_int(key);
    if (v < lo || v > hi || v < INT32_MIN || v > INT32_MAX)
      throw error("config key '" + key + "' is " + std::to_string(v) + ", out of range " + std::to_string(lo) + ".." +
                  std::to_string(hi));
    return int(v);
  }
  // A finite number: no key of ours means NaN or an infinity, and one read as a float
  // must stay finite as a float (1e39 is inf there).
  double config_double(const std::string& key) const {
    const std::string& v = config_string(key);
    double r = 0;
    try {
      size_t pos;
      r = std::stod(v, &pos);
      if (pos != v.size()) throw std::exception();
    } catch (...) {
      throw error("config key '" + key + "' is '" + v + "', not a number");
    }
    if (!std::isfinite(float(r))) throw error("config key '" + key + "' is '" + v + "', not a finite number");
    return r;
  }

  // ---- tensors, kept in insertion order so the same saves give the same bytes ----
  template <class T>
  void put(const std::string& name, const Shape& shape, const T* data) {
    BlobTensor t;
    t.dtype = dtype_of<T>();
    t.dims.assign(shape.begin(), shape.end());
    t.bytes.assign(reinterpret_cast<const char*>(data), sizeof(T) * size_t(shape.numel()));
    add(name, std::move(t));
  }
  template <class T>
  void put(const std::string& name, const Tensor<T>& t) {
    put(name, t.shape(), t.data());
  }
  void put_i64(const std::string& name, int64_t v) { put(name, Shape{1}, &v); }
  void put_f64(const std::string& name, double v) { put(name, Shape{1}, &v); }

  bool has(const std::string& name) const { return index_.count(name) != 0; }
  const std::vector<std::pair<std::string, BlobTensor>>& tensors() const { return tensors_; }
  const BlobTensor& at(const std::string& name) const {
    auto it = index_.find(name);
    if (it == index_.end()) throw error("tensor '" + name + "' is missing");
    return tensors_[it->second].second;
  }

  // Copies tensor `name` into `out` after checking its shape. f32 and f64 convert into
  // each other (float weights feed a double gradient check); integers must match.
  template <class T>
  void read(const std::string& name, const Shape& expected, T* out) const {
    const BlobTensor& t = at(name);
    Shape got(t.dims.begin(), t.dims.end());
    if (got != expected) throw error("tensor '" + name + "' has shape " + got.str() + ", expected " + expected.str());
    const size_t n = size_t(t.numel());
    if (t.dtype == dtype_of<T>()) {
      std::memcpy(out, t.bytes.data(), n * sizeof(T));
      if constexpr (std::is_floating_point_v<T>) check_finite(name, out, n);
    } else if constexpr (std::is_floating_point_v<T>) {
      if (t.dtype == DType::F32) convert<float>(t, out, n);
      else if (t.dtype == DType::F64) convert<double>(t, out, n);
      else
        throw error("tensor '" + name + "' has dtype " + dtype_name(t.dtype) + ", expected " +
                    dtype_name(dtype_of<T>()));
      check_finite(name, out, n);
    } else {
      throw error("tensor '" + name + "' has dtype " + dtype_name(t.dtype) + ", expected " + dtype_name(dtype_of<T>()));
    }
  }
  template <class T>
  Tensor<T> tensor(const std::string& name, const Shape& expected) const {
    Tensor<T> out(expected);
    read(name, expected, out.data());
    return out;
  }
  int64_t get_i64(const std::string& name) const {
    int64_t v;
    read(name, Shape{1}, &v);
    return v;
  }
  double get_f64(const std::string& name) const {
    double v;
    read(name, Shape{1}, &v);
    return v;
  }

  // ---- bytes and files ----
  std::string serialize() const {
    std::string out;
    out.append(kMagic, 8);
    put_u32(out, kVersion);
    put_u32(out, 0);  // flags, reserved
    put_u64(out, 0);  // file size, patched below
    put_str(out, kind_);
    put_u32(out, uint32_t(config_.size()));
    for (auto& [k, v] : config_) {
      put_str(out, k);
      put_str(out, v);
    }
    put_u32(out, uint32_t(tensors_.size()));
    for (auto& [name, t] : tensors_) {
      put_str(out, name);
      put_u32(out, uint32_t(t.dtype));
      put_u32(out, uint32_t(t.dims.size()));
      for (int64_t d : t.dims) put_u64(out, uint64_t(d));
      out.append((kAlign - out.size() % kAlign) % kAlign, '\0');
      out += t.bytes;
    }
    uint64_t total = out.size() + 4;
    std::memcpy(&out[16], &total, 8);
    put_u32(out, crc32(out.data(), out.size()));
    return out;
  }

  static Blob parse(std::string_view bytes, const std::string& source) {
    Blob b;
    b.source_ = source;
    Reader r{bytes, 0, &b};
    const size_t n = bytes.size();
    // Check in the order that gives the most useful message: is it a blob at all, one
    // this build understands, complete, intact — and only then parse it.
    if (n < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0) {
      bool prefix = n < 8 && std::memcmp(bytes.data(), kMagic, n) == 0;
      throw b.error(prefix ? "truncated: " + std::to_string(n) + " bytes, shorter than the header"
                           : std::string("not an nnshade blob (bad magic; expected \"NNSBLOB\\0\")"));
    }
    if (n < kFixedHeader) throw b.error("truncated: " + std::to_string(n) + " bytes, shorter than the header");
    r.pos = 8;
    uint32_t version = r.u32();
    if (version != kVersion)
      throw b.error("format version " + std::to_string(version) + " is not supported (this build reads version " +
                    std::to_string(kVersion) + ")");
    r.u32();  // flags: none defined in version 1
    uint64_t declared = r.u64();
    if (declared > n) throw b.error("truncated: " + std::to_string(n) + " of " + std::to_string(declared) + " bytes");
    if (declared < n) throw b.error(std::to_string(n - declared) + " unexpected bytes after the end of the blob");
    if (declared < kFixedHeader + 4) throw b.error("malformed: declared size is too small");
    uint32_t stored, computed = crc32(bytes.data(), n - 4);
    std::memcpy(&stored, bytes.data() + n - 4, 4);
    if (stored != computed)
      throw b.error("checksum mismatch (stored " + hex(stored) + ", computed " + hex(computed) +
                    "): the file is corrupt");
    r.end = n - 4;
    b.kind_ = r.str();
    for (uint32_t i = 0, nc = r.u32(); i < nc; ++i) {
      std::string k = r.str();
      b.config_[k] = r.str();
    }
    for (uint32_t i = 0, nt = r.u32(); i < nt; ++i) {
      std::string name = r.str();
      BlobTensor t;
      uint32_t dt = r.u32();
      if (dt < 1 || dt > 4) throw b.error("tensor '" + name + "' has unknown dtype " + std::to_string(dt));
      t.dtype = DType(dt);
      uint32_t ndim = r.u32();
      if (ndim > uint32_t(Shape::kMaxDims))
        throw b.error("tensor '" + name + "' has " + std::to_string(ndim) + " dimensions (at most 6)");
      uint64_t numel = 1;
      for (uint32_t k = 0; k < ndim; ++k) {
        uint64_t d = r.u64();
        if (d > (uint64_t(1) << 40) || (d && numel > (uint64_t(1) << 40) / d))
          throw b.error("tensor '" + name + "' has an implausible shape");
        numel *= d;
        t.dims.push_back(int64_t(d));
      }
      r.pos += (kAlign - r.pos % kAlign) % kAlign;
      t.bytes = std::string(r.take(numel * dtype_size(t.dtype), name));
      b.add(name, std::move(t));
    }
    if (r.pos != r.end) throw b.error("malformed: bytes left over after the last tensor");
    return b;
  }

  void save(const std::string& path) const { write_file_atomic(path, serialize()); }
  static Blob load(const std::string& path) { return parse(read_file(path), path); }

  // Every failure names the blob and the problem.
  std::runtime_error error(const std::string& what) const {
    return std::runtime_error("blob '" + source_ + "': " + what);
  }

 private:
  struct Reader {
    std::string_view bytes;
    size_t pos;
    const Blob* blob;
    size_t end = 0;
    std::string_view take(uint64_t k, const std::string& what) {
      size_t lim = end ? end : bytes.size();
      if (pos > lim || k > lim - pos) throw blob->error("malformed: " + what + " runs past the end");
      std::string_view s = bytes.substr(pos, size_t(k));
      pos += size_t(k);
      return s;
    }
    uint32_t u32() {
      uint32_t v;
      std::memcpy(&v, take(4, "a field").data(), 4);
      return v;
    }
    uint64_t u64() {
      uint64_t v;
      std::memcpy(&v, take(8, "a field").data(), 8);
      return v;
    }
    std::string str() {
      uint32_t len = u32();
      return std::string(take(len, "a string"));
    }
  };

  // Every real value a reader takes is finite: no weight, statistic, optimizer moment or
  // learning rate of ours is NaN or infinite, and one that is poisons every output while
  // the run exits 0 (a CRC only says the bytes are the ones written).
  template <class T>
  void check_finite(const std::string& name, const T* v, size_t n) const {
    if (all_finite(v, int64_t(n))) return;
    size_t i = 0;
    while (i < n && std::isfinite(v[i])) ++i;
    throw error("tensor '" + name + "' holds a non-finite value (" + (std::isnan(v[i]) ? "NaN" : "Inf") +
                ") at index " + std::to_string(i));
  }

  void add(const std::string& name, BlobTensor t) {
    if (has(name)) throw error("tensor '" + name + "' is stored twice");
    index_[name] = tensors_.size();
    tensors_.emplace_back(name, std::move(t));
  }
  template <class From, class To>
  static void convert(const BlobTensor& t, To* out, size_t n) {
    for (size_t i = 0; i < n; ++i) {
      From v;
      std::memcpy(&v, t.bytes.data() + i * sizeof(From), sizeof(From));
      out[i] = To(v);
    }
  }
  static void put_u32(std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }
  static void put_u64(std::string& s, uint64_t v) { s.append(reinterpret_cast<const char*>(&v), 8); }
  static void put_str(std::string& s, const std::string& v) {
    put_u32(s, uint32_t(v.size()));
    s += v;
  }
  static std::string hex(uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%08x", v);
    return buf;
  }

  std::string kind_, source_ = "<memory>";
  std::map<std::string, std::string> config_;
  std::vector<std::pair<std::string, BlobTensor>> tensors_;
  std::unordered_map<std::string, size_t> index_;
};

}  // namespace nns
