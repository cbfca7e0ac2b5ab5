"""Shared helpers of the studies' checks (check_study_*.py, run by CTest as study.*; see
Tools/CMakeLists.txt). Plain python3 with numpy: no ParaView."""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
failures = []


def tool_from_argv():
    tool = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("HAIR_STUDY")
    if not tool or not os.path.isfile(tool):
        sys.exit(f"give the path of the built hair_study (<build>/bin/hair_study; got {tool!r})")
    return tool


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what)
    if not condition:
        failures.append(what)


def png_ok(path):
    if not os.path.exists(path) or os.path.getsize(path) < 10000:
        return False
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


def finish():
    print(f"{len(failures)} failed" if failures else "all checks passed")
    sys.exit(1 if failures else 0)
