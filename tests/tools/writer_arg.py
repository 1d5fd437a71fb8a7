"""The one argument the tools' tests take: the C++ program that writes their blobs
(ctest passes its path, tests/CMakeLists.txt)."""
import sys


def pop_writer(usage):
    if len(sys.argv) < 2:
        print(usage, file=sys.stderr)
        sys.exit(2)
    return sys.argv.pop(1)  # unittest.main() must not see it
