#!/usr/bin/env bash
# Core and its tests built with AddressSanitizer and UndefinedBehaviorSanitizer (GCC, no
# ParaView) in build-asan/, then the Core CTest label run there: any report fails it.
# CI runs it after Scripts/test.sh and the fuzzer when HAIR_CI_SANITIZE=1 (.ci/run);
# docs/robustness.md has what it covers, what was measured, and the GCC 12 false positive
# that was looked for and not seen at -O1.
#   bash Scripts/sanitize.sh            the whole Core suite (HAIR_ASAN_BUILD_DIR to build elsewhere)
#   bash Scripts/sanitize.sh ci         the subset CI runs (.ci/run): the state-file reader and
#                                       the fuzz corpus replay, the frame loop, both models'
#                                       steps, the contact module, and Core under MPI on 2 ranks
#                                       (docs/robustness.md, "The sanitizer build")
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${HAIR_ASAN_BUILD_DIR:-$ROOT/build-asan}"
JOBS="${HAIR_JOBS:-2}"
MODE="${1:-all}"
bash "$ROOT/Scripts/install-deps.sh"

# The CI subset: what reads untrusted input (the reader, the replay of the fuzz corpus and
# its regressions), the frame loop that writes, streams and resumes state files (Simulation,
# runs killed and resumed), each
# model's step with its body contacts (projective, its friction, the Super-Helix's contacts),
# hair–hair contacts, and Core's MPI ranks (on 2 ranks, and on 4 for the tests that compare
# 1, 2 and 4). Of these executables' tests two are left to the whole suite: the Super-Helix's
# convergence through contact (162 s under ASan, a study of the step's order whose code the
# other contact tests run) and the resume with the sub-step controller (290 s under ASan; the
# other kill tests run the resume's code).
ci_targets=(replay_state_file test_state_file test_state_file_bad_input test_simulation
  test_resume test_projective test_projective_friction test_superhelix_body_contacts
  test_hair_hair_contacts mpi_simulation)

start=$(date +%s)
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  # -O1: the sanitizers' usual level (fast enough to run the suite, stacks still readable).
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g" \
    -DHAIR_BUILD_PARAVIEW=OFF -DHAIR_BUILD_BENCHMARKS=OFF -DHAIR_SANITIZE=address,undefined
fi
if [ "$MODE" = ci ]; then
  cmake --build "$BUILD" -j "$JOBS" --target "${ci_targets[@]}"
else
  cmake --build "$BUILD" -j "$JOBS"
fi
built=$(date +%s)

# detect_leaks: on (LeakSanitizer, part of ASan). halt_on_error: the first report fails the
# test. The suppressions name the one report that is not ours (see the file).
# allocator_may_return_null: what the system cannot give is NULL, as with glibc in
# ParaView (the fuzz replay has a file declaring a 390 GB HDF5 metadata entry).
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=1:allocator_may_return_null=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$ROOT/Testing/Sanitizers/lsan.supp:print_suppressions=0"
cd "$BUILD"
# CTest's MPI test runs below instead, with Open MPI's own leaks suppressed.
if [ "$MODE" = ci ]; then
  # Only the subset's executables are built, so only their tests are known to CTest.
  ctest --output-on-failure -j "$JOBS" --timeout 1800 -L core \
    -E '^mpi\.|StepsConvergeThroughContactWithTheSphere|SuperHelixWithATolerancesSubSteps'
else
  ctest --output-on-failure -j "$JOBS" --timeout 1800 -L core -E '^mpi\.'
fi
# Core under MPI; the sanitizers' options reach every rank (-x). Open MPI leaves its own
# allocations at MPI_Finalize: suppressed by module (Testing/Sanitizers/lsan-mpi.supp), its
# components kept loaded so that their frames have names, full stacks for the matching.
export ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0"
export LSAN_OPTIONS="suppressions=$ROOT/Testing/Sanitizers/lsan-mpi.supp:print_suppressions=0"
export OMPI_MCA_mca_base_component_disable_dlclose=1
for ranks in 2 4; do
  mpirun --allow-run-as-root --oversubscribe -np "$ranks" -x ASAN_OPTIONS -x UBSAN_OPTIONS \
    -x LSAN_OPTIONS -x OMPI_MCA_mca_base_component_disable_dlclose \
    "$BUILD/Testing/mpi_simulation"
done
echo "sanitize.sh ($MODE): build $((built - start)) s, tests $(($(date +%s) - built)) s"
