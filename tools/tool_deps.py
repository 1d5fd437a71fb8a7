"""Imports a tool's third-party module, or exits with a message a person can act on.

    from tool_deps import require
    np = require("numpy", "python3-numpy")

A `python3` earlier on PATH (pyenv, a venv) often lacks the Debian packages that
scripts/install-deps puts in /usr/bin/python3; a bare ModuleNotFoundError does not say
so. The message names the interpreter that was used, the Debian package, and any other
interpreter on this machine that does have the module.
"""
import os
import shutil
import subprocess
import sys

CANDIDATES = ("/usr/bin/python3", "python3", "python3.11")


def interpreters_with(module):
    """Other python3 interpreters on this machine that import `module` (-E: their own
    installation, whatever PYTHONPATH says)."""
    here = os.path.realpath(sys.executable)
    found = []
    for name in CANDIDATES:
        exe = shutil.which(name)
        if not exe or os.path.realpath(exe) == here or exe in found:
            continue
        try:
            ok = subprocess.run([exe, "-E", "-c", f"import {module}"], capture_output=True, timeout=60).returncode == 0
        except (OSError, subprocess.TimeoutExpired):
            ok = False
        if ok:
            found.append(exe)
    return found


def require(module, package):
    try:
        return __import__(module)
    except ImportError as e:
        tool = os.path.basename(sys.argv[0]) or "python"
        lines = [f"{tool}: error: the Python module '{module}' is missing for {sys.executable} "
                 f"(Python {sys.version.split()[0]}): {e}",
                 f"  install the Debian package {package} (scripts/install-deps does)"]
        for exe in interpreters_with(module):
            lines.append(f"  or run the tool with {exe}, which has it")
        print("\n".join(lines), file=sys.stderr)
        sys.exit(2)
