#!/usr/bin/env python3
"""Reads an nnshade blob (weights or checkpoint; docs/weights-format.md) with numpy only.

    python3 tools/read_blob.py model.blob        # prints kind, config and tensors

    from read_blob import load
    kind, config, tensors = load("model.blob")   # tensors: name -> numpy array
"""
import os
import struct
import sys
import zlib

from tool_deps import require

np = require("numpy", "python3-numpy")

MAGIC = b"NNSBLOB\0"
VERSION = 1
ALIGN = 64
MAX_DIMS = 6
DTYPES = {1: np.dtype("<f4"), 2: np.dtype("<f8"), 3: np.dtype("<u8"), 4: np.dtype("<i8")}
DTYPE_NAMES = {1: "f32", 2: "f64", 3: "u64", 4: "i64"}


class BlobError(ValueError):
    """A file that is not a valid blob; the message names the file and the problem."""


def parse(data, source="<bytes>"):
    """Parses blob bytes into (kind, config dict, dict name -> numpy array)."""
    def fail(what):
        raise BlobError(f"blob '{source}': {what}")

    n = len(data)
    if n < 8 or data[:8] != MAGIC:
        if n < 8 and MAGIC.startswith(bytes(data)):
            fail(f"truncated: {n} bytes, shorter than the header")
        fail('not an nnshade blob (bad magic; expected "NNSBLOB\\0")')
    if n < 24:
        fail(f"truncated: {n} bytes, shorter than the header")
    version, _flags, declared = struct.unpack_from("<IIQ", data, 8)
    if version != VERSION:
        fail(f"format version {version} is not supported (this reader reads version {VERSION})")
    if declared > n:
        fail(f"truncated: {n} of {declared} bytes")
    if declared < n:
        fail(f"{n - declared} unexpected bytes after the end of the blob")
    if declared < 28:
        fail("malformed: declared size is too small")
    (stored,) = struct.unpack_from("<I", data, n - 4)
    computed = zlib.crc32(data[: n - 4]) & 0xFFFFFFFF
    if stored != computed:
        fail(f"checksum mismatch (stored 0x{stored:08x}, computed 0x{computed:08x}): the file is corrupt")

    end = n - 4
    pos = 24

    def take(k, what):
        nonlocal pos
        if k > end - pos:
            fail(f"malformed: {what} runs past the end")
        chunk = data[pos : pos + k]
        pos += k
        return chunk

    def u32():
        return struct.unpack("<I", take(4, "a field"))[0]

    def u64():
        return struct.unpack("<Q", take(8, "a field"))[0]

    def string():
        return bytes(take(u32(), "a string")).decode("utf-8")

    kind = string()
    config = {}
    for _ in range(u32()):
        key = string()
        config[key] = string()
    tensors = {}
    for _ in range(u32()):
        name = string()
        code = u32()
        if code not in DTYPES:
            fail(f"tensor '{name}' has unknown dtype {code}")
        ndim = u32()
        if ndim > MAX_DIMS:
            fail(f"tensor '{name}' has {ndim} dimensions (at most {MAX_DIMS})")
        dims = tuple(u64() for _ in range(ndim))
        pos += (ALIGN - pos % ALIGN) % ALIGN
        dtype = DTYPES[code]
        numel = int(np.prod(dims, dtype=np.uint64)) if dims else 1
        raw = take(numel * dtype.itemsize, f"tensor '{name}'")
        if name in tensors:
            fail(f"tensor '{name}' is stored twice")
        tensors[name] = np.frombuffer(raw, dtype=dtype).reshape(dims).copy()
    if pos != end:
        fail("malformed: bytes left over after the last tensor")
    return kind, config, tensors


def load(path):
    """Reads the blob at `path`: returns (kind, config dict, dict name -> numpy array)."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise BlobError(f"cannot open '{path}': {e.strerror}") from e
    return parse(data, path)


def summary(path):
    kind, config, tensors = load(path)
    lines = [f"{path}: kind '{kind}', {len(config)} config keys, {len(tensors)} tensors"]
    lines += [f"  {k} = {v}" for k, v in config.items()]
    total = 0
    for name, a in tensors.items():
        total += a.size
        shape = "[" + ",".join(str(d) for d in a.shape) + "]"
        stats = ""
        if a.size and a.dtype.kind == "f":
            stats = f"  min {a.min():.4g} max {a.max():.4g} mean {a.mean():.4g}"
        code = next(c for c, d in DTYPES.items() if d == a.dtype)
        lines.append(f"  {name:40s} {DTYPE_NAMES[code]} {shape}{stats}")
    lines.append(f"  {total} values in total")
    return "\n".join(lines)


def for_each_file(argv, usage, summarise):
    """The tools' command line: prints summarise(path) for every FILE argument; a bad
    file is reported (naming it) and the others still run; exit status 1 if any failed."""
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(usage)
        return 0 if len(argv) >= 2 else 2
    status = 0
    for path in argv[1:]:
        try:
            print(summarise(path))
        except BlobError as e:
            print(f"{os.path.basename(argv[0])}: error: {e}", file=sys.stderr)
            status = 1
    return status


def main(argv):
    return for_each_file(argv, "usage: read_blob.py FILE...  (prints each blob's kind, config and tensors)", summary)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
