#!/usr/bin/env python3
"""The include graph points one way (DEVELOPERS.md draws it): this reads every
#include "..." of the tree and fails naming each file that reaches a folder its
layer may not use. It also fails on a file whose code opens a namespace other than its
folder's (NAMESPACE below), so that a name's namespace says where its file is. ctest
runs it (tools.layering), so a move that bends the graph fails CI.

    apps -> runs -> models, classical_ao -> nn, optim -> core
    screen_space: core, data's view;  data: core;  render: core, data;  report: core
"""
import os
import re
import sys

# folder -> the top-level folders its files may include (itself always allowed)
ALLOWED = {
    "core": set(),
    "nn": {"core"},
    "optim": {"core", "nn"},
    "data": {"core"},
    "render": {"core", "data"},
    "report": {"core"},
    "screen_space": {"core", "data"},
    "classical_ao": {"core", "data", "screen_space"},
    "models": {"core", "nn", "optim", "data", "screen_space"},
    "runs": {"core", "nn", "optim", "data", "report", "screen_space", "classical_ao", "models"},
    "apps": {"core", "nn", "optim", "data", "render", "report", "screen_space", "classical_ao", "models", "runs"},
    "fixtures": {"core", "data"},
    "benchmarks": {"core", "nn", "optim", "data", "render", "report", "screen_space", "classical_ao", "models",
                   "runs", "fixtures"},
    "fuzz": {"core", "nn", "optim", "data", "render", "report", "screen_space", "classical_ao", "models", "runs"},
    # An engine's view of the exported shaders: the files and the G-buffer, never the model code.
    "examples": {"core", "data", "screen_space", "apps"},
}
# folder -> the namespace its files open (a folder not listed takes its parent's). The
# foundation (core, nn, optim) is nns itself; each model of models/ is its own namespace;
# a namespace may nest below its folder's (nns::data::blender, nns::screen_space::simd).
NAMESPACE = {
    "core": "nns", "nn": "nns", "optim": "nns", "models": "nns",
    "models/gi": "nns::gi", "models/nnao": "nns::nnao",
    "data": "nns::data", "render": "nns::render", "report": "nns::report",
    "screen_space": "nns::screen_space", "classical_ao": "nns::classical_ao",
    "runs": "nns::runs", "apps": "nns::apps", "fixtures": "nns::fixtures",
    "benchmarks": "nns::benchmarks", "fuzz": "nns::fuzz", "tests": "nns::testing",
}
# The foundation's implementation details live beside it (nns::gemm_detail).
FOUNDATION_DETAIL = re.compile(r"^nns::\w+_detail$")
OPENS = re.compile(r"^namespace\s+(nns(?:::\w+)*)\s*\{", re.M)
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def sources(root, top):
    """(path, text) of every .h and .cpp below root/top."""
    for dirpath, _, files in os.walk(os.path.join(root, top)):
        for f in sorted(files):
            if f.endswith((".h", ".cpp")):
                path = os.path.join(dirpath, f)
                with open(path, encoding="utf-8", errors="replace") as fh:
                    yield path, fh.read()


def main(root):
    bad = []
    for top, allowed in ALLOWED.items():
        for path, text in sources(root, top):
            for inc in INCLUDE.findall(text):
                first = inc.split("/")[0]
                if "/" not in inc or first == top:
                    continue
                if first not in allowed:
                    bad.append(f"{os.path.relpath(path, root)}: includes {inc} ({top} may use: "
                               f"{', '.join(sorted(allowed)) or 'only itself'})")
    wrong_ns = namespace_errors(root)
    for b in bad + wrong_ns:
        print(b)
    print(f"layering: {len(bad)} include(s) against the direction of the graph, "
          f"{len(wrong_ns)} namespace(s) that are not their folder's")
    return 1 if bad or wrong_ns else 0


def expected_namespace(rel_dir):
    parts = rel_dir.split(os.sep)
    for n in range(len(parts), 0, -1):
        key = "/".join(parts[:n])
        if key in NAMESPACE:
            return NAMESPACE[key]
    return None


def namespace_errors(root):
    bad = []
    for top in NAMESPACE:
        if "/" in top:
            continue
        for path, text in sources(root, top):
            want = expected_namespace(os.path.relpath(os.path.dirname(path), root))
            for ns in OPENS.findall(text):
                ok = ns == want or ns.startswith(want + "::") if want != "nns" else (
                    ns == "nns" or FOUNDATION_DETAIL.match(ns))
                if not ok:
                    bad.append(f"{os.path.relpath(path, root)}: opens namespace {ns}; its folder's is {want}")
    return bad


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")))
