#!/usr/bin/env bash
# Fuzzes the state-file reader (Testing/Fuzz/fuzz_state_file.cxx) with libFuzzer for a bounded
# time: clang, AddressSanitizer and UndefinedBehaviorSanitizer, in build-fuzz/, over a copy of
# the seed corpus (Testing/Fuzz/corpus/; the copy grows, the repository's does not). Fails on
# any crash, sanitizer report, out-of-memory or input slower than the timeout; the input is
# left in build-fuzz/artifacts/ (keep it in Testing/Fuzz/regressions/ once fixed).
#   bash Scripts/fuzz.sh [seconds]      (default 300, what CI runs; docs/robustness.md)
# HAIR_FUZZ_SEED (default 24) fixes libFuzzer's random seed, and each run starts from the
# repository's corpus, so that a CI failure can be replayed exactly: CI explores the first
# minutes of the same search every time (as far as the machine's speed takes it), and a
# longer run locally with the same seed covers what CI will see. HAIR_FUZZ_SEED=0 draws a
# new seed, and HAIR_FUZZ_KEEP=1 keeps growing build-fuzz/corpus/ across runs: exploration.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${HAIR_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
JOBS="${HAIR_JOBS:-2}"
SECONDS_TO_RUN="${1:-300}"
bash "$ROOT/Scripts/install-deps.sh"

start=$(date +%s)
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g" \
    -DHAIR_BUILD_PARAVIEW=OFF -DHAIR_BUILD_BENCHMARKS=OFF -DHAIR_BUILD_TESTING=OFF \
    -DHAIR_BUILD_FUZZ=ON -DHAIR_SANITIZE=address,undefined
fi
cmake --build "$BUILD" -j "$JOBS" --target fuzz_state_file
built=$(date +%s)

corpus="$BUILD/corpus"
if [ "${HAIR_FUZZ_KEEP:-0}" != 1 ]; then
  rm -rf "$corpus"
fi
mkdir -p "$corpus" "$BUILD/artifacts"
cp -n "$ROOT"/Testing/Fuzz/corpus/* "$corpus"/
# allocator_may_return_null: an allocation the system cannot give returns NULL, as glibc's
# does in ParaView (HDF5 then reports an error), instead of aborting the fuzzer: HDF5 asks
# for a metadata entry's size as the file declares it before reading the rest (a file
# declaring 390 GB made ASan abort where glibc returns NULL).
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=1:allocator_may_return_null=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$ROOT/Testing/Sanitizers/lsan.supp:print_suppressions=0"
# -timeout=10: an input that takes 10 s is a hang (a damaged file must be refused within
# seconds). -rss_limit_mb=4096: the reader must not use memory the file does not justify;
# memory reserved and never touched (-malloc_limit_mb, by default the RSS limit, would count
# it) is not a user's problem, so only what the process touches is limited.
# The whole log goes to build-fuzz/fuzz.log; printed: the report of a failure (with its
# stack, which a plain tail cut off) or the final statistics.
log="$BUILD/fuzz.log"
status=0
"$BUILD/bin/fuzz_state_file" -max_total_time="$SECONDS_TO_RUN" -timeout=10 -rss_limit_mb=4096 -malloc_limit_mb=1048576 -seed="${HAIR_FUZZ_SEED:-24}" \
  -artifact_prefix="$BUILD/artifacts/" -print_final_stats=1 "$corpus" >"$log" 2>&1 || status=$?
if [ "$status" -ne 0 ]; then
  sed -n '/^==[0-9]*==\(ERROR\|WARNING\)\|^SUMMARY\|runtime error\|ALARM\|Test unit written/,$p' "$log" | head -n 120
else
  tail -n 12 "$log"
fi
echo "fuzz.sh: build $((built - start)) s, fuzzing ${SECONDS_TO_RUN} s, log $log"
exit "$status"
