#!/usr/bin/env python3
"""Fails on a comment that cites an issue number ("issue 13", "Issue #5"): a reader of
the repository cannot open the tracker, so a comment says the reason itself.

usage: check_comments.py ROOT
"""
import pathlib
import re
import sys

FOLDERS = ["apps", "benchmarks", "classical_ao", "core", "data", "examples", "fixtures", "fuzz", "models", "nn",
           "optim", "render", "report", "runs", "screen_space", "scripts", "tests", "tools"]
SUFFIXES = {".h", ".cpp", ".py", ".sh", ".frag", ".vert", ".glsl", ".cmake", ".txt"}
ISSUE = re.compile(r"\b[Ii]ssue\s*#?\s*\d+")


def main(root):
    root = pathlib.Path(root)
    bad = []
    for folder in FOLDERS:
        for path in sorted((root / folder).rglob("*")):
            # scripts/ holds shell scripts without a suffix
            if (path.suffix not in SUFFIXES and not (folder == "scripts" and path.suffix == "")) or not path.is_file() \
                    or path.name == "check_comments.py":
                continue
            for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                if ISSUE.search(line):
                    bad.append(f"{path.relative_to(root)}:{number}: {line.strip()}")
    for b in bad:
        print(b)
    if bad:
        print(f"{len(bad)} line(s) cite an issue number: say the reason instead")
        return 1
    print("no comment cites an issue number")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
