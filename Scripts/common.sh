# Sourced by demo.sh and test.sh: installs what is missing, then configures and builds
# (HAIR_TARGETS, set by the sourcing script: only those targets and what they need; unset:
# everything, the tests and benchmarks included).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${HAIR_BUILD_DIR:-$ROOT/build}"
JOBS="${HAIR_JOBS:-2}"

bash "$ROOT/Scripts/install-deps.sh"

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release
fi
# shellcheck disable=SC2086 # HAIR_TARGETS is a list of target names
cmake --build "$BUILD" -j "$JOBS" ${HAIR_TARGETS:+--target $HAIR_TARGETS}
PLUGIN="$BUILD/lib/paraview-5.11/plugins/HairDynamics/HairDynamics.so"
