#!/usr/bin/env python3
"""The defaults the docs state are the ones the commands ship.

docs/nnao.md and docs/gan.md each hold a table of the shipped defaults between
<!-- defaults:APP --> and <!-- /defaults:APP --> markers, one row per flag:
| `--flag` | value | what |. This test runs `APP --help`, reads each flag's
"(default V...)" and fails on any row whose value differs, on a row naming a flag the
command does not have, and on a table that leaves out one of the defaults that matter
(blur passes and edge terms, the radius term ceiling, the network's size, the epochs;
train-gan's model and rates). docs/weights-format.md's sentence on the default blur
(P, c, q) is checked against the same --help.

    test_docs_defaults.py TRAIN_NNAO TRAIN_GAN REPO_ROOT
"""
import os
import re
import subprocess
import sys

REQUIRED = {
    "train-nnao": ["--features", "--directions", "--steps", "--bands", "--hidden", "--dropout", "--gamma",
                   "--epochs", "--blur-passes", "--blur-depth", "--blur-normal-power", "--radius-term-max"],
    "train-gan": ["--mode", "--size", "--ngf", "--ndf", "--levels", "--epochs", "--loss", "--lr", "--lr-d",
                  "--residual", "--validation-fraction"],
}
DOCS = {"train-nnao": "docs/nnao.md", "train-gan": "docs/gan.md"}

failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL: " + msg)


def help_defaults(binary):
    """{flag: default text} from `binary --help`."""
    out = subprocess.run([binary, "--help"], capture_output=True, text=True, timeout=120)
    if out.returncode != 0:
        raise SystemExit(f"{binary} --help exited {out.returncode}: {out.stderr}")
    found = {}
    for line in out.stdout.splitlines():
        m = re.match(r"^\s+(--[a-z0-9-]+)\b", line)
        # "(default V)" or "(default V, range [lo, hi])", a bound open as in "[0, inf)"
        d = re.search(r"\(default ([^,()]+)(?:, range [\[(][^\])]*[\])])?\)\s*$", line)
        if m and d:
            found[m.group(1)] = d.group(1).strip()
    if not found:
        raise SystemExit(f"{binary} --help: no '(default ...)' found; has the usage format changed?")
    return found


def doc_table(path, app):
    """{flag: value} from the marked defaults table of a doc."""
    text = open(path, encoding="utf-8").read()
    m = re.search(rf"<!-- defaults:{app} -->\n(.*?)<!-- /defaults:{app} -->", text, re.S)
    if not m:
        fail(f"{path}: no table between <!-- defaults:{app} --> and <!-- /defaults:{app} -->")
        return {}
    rows = {}
    for line in m.group(1).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or not cells[0].startswith("`--"):
            continue
        rows[cells[0].strip("`")] = cells[1].strip("`* ")
    if not rows:
        fail(f"{path}: the defaults table has no rows")
    return rows


def same(doc_value, help_value):
    try:
        return float(doc_value) == float(help_value)
    except ValueError:
        return doc_value == help_value


def main():
    if len(sys.argv) != 4:
        raise SystemExit(__doc__)
    binaries = {"train-nnao": sys.argv[1], "train-gan": sys.argv[2]}
    root = sys.argv[3]
    helps = {}
    for app, binary in binaries.items():
        helps[app] = defaults = help_defaults(binary)
        doc = os.path.join(root, DOCS[app])
        rows = doc_table(doc, app)
        for flag, value in rows.items():
            if flag not in defaults:
                fail(f"{DOCS[app]}: {flag} is not a flag with a default in `{app} --help`")
            elif not same(value, defaults[flag]):
                fail(f"{DOCS[app]}: {flag} is '{value}' in the defaults table, '{defaults[flag]}' in `{app} --help`")
        for flag in REQUIRED[app]:
            if flag not in rows:
                fail(f"{DOCS[app]}: the defaults table leaves out {flag} (`{app} --help`: {defaults.get(flag)})")
        print(f"{app}: {len(rows)} defaults in {DOCS[app]} checked against --help")

    # docs/weights-format.md states the default model's blur in prose.
    wf = os.path.join(root, "docs/weights-format.md")
    text = " ".join(open(wf, encoding="utf-8").read().split())
    m = re.search(r"default model has P = (\d+), c = ([0-9.]+), q = (\d+)", text)
    if not m:
        fail("docs/weights-format.md: no 'default model has P = .., c = .., q = ..' sentence")
    else:
        d = helps["train-nnao"]
        for name, value, flag in zip("Pcq", m.groups(), ("--blur-passes", "--blur-depth", "--blur-normal-power")):
            if not same(value, d.get(flag, "?")):
                fail(f"docs/weights-format.md: {name} = {value}, `train-nnao --help` {flag} {d.get(flag)}")

    if failures:
        print(f"{len(failures)} disagreement(s) between the docs and the code")
        return 1
    print("the docs' defaults agree with --help")
    return 0


if __name__ == "__main__":
    sys.exit(main())
