#!/usr/bin/env bash
# Every test: installs, builds, checks formatting, runs the C++ and pvpython tests (CTest).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

# Format drift fails the tests.
cd "$ROOT"
files=$(git ls-files '*.h' '*.cxx' 2>/dev/null || find Core Filters Testing -name '*.h' -o -name '*.cxx')
if ! clang-format --dry-run --Werror $files; then
  echo "test.sh: the files above are not clang-format clean: run clang-format -i on them" >&2
  exit 1
fi

cd "$BUILD"
ctest --output-on-failure -j "$JOBS" --timeout 1200
