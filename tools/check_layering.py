#!/usr/bin/env python3
"""The include graph points one way (DEVELOPERS.md draws it): this reads every
#include "..." of the tree and fails naming each file that reaches a folder its
layer may not use. ctest runs it (tools.layering), so a move that bends the graph
fails CI.

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
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def main(root):
    bad = []
    for top, allowed in ALLOWED.items():
        for dirpath, _, files in os.walk(os.path.join(root, top)):
            for f in files:
                if not f.endswith((".h", ".cpp")):
                    continue
                path = os.path.join(dirpath, f)
                with open(path, encoding="utf-8", errors="replace") as fh:
                    text = fh.read()
                for inc in INCLUDE.findall(text):
                    first = inc.split("/")[0]
                    if "/" not in inc or first == top:
                        continue
                    if first not in allowed:
                        bad.append(f"{os.path.relpath(path, root)}: includes {inc} ({top} may use: "
                                   f"{', '.join(sorted(allowed)) or 'only itself'})")
    for b in bad:
        print(b)
    print(f"layering: {len(bad)} include(s) against the direction of the graph")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")))
