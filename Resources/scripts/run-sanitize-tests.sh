#!/usr/bin/env bash
# The sanitizer step of run-tests.sh (and of CI): configures a build with AddressSanitizer + UndefinedBehaviorSanitizer
# (TISSUEMOSAIC_SANITIZE, cmake/Sanitizers.cmake; CUDA and GUI off), builds only the labelled subset's driver
# (TissueMosaicSanitizeTests: the readers of outside input on a library of their own, Testing/SanitizeSubset.cmake),
# and the OpenIGTLink fuzz targets as corpus replays, and runs that subset (ctest label "sanitize"). Exits non-zero on failure.
# Extra arguments go to ctest. docs/TESTING.md says what it covers and how long it takes.
#
# Environment (all optional): TM_SANITIZE_BUILD_DIR (default <repo>/build-asan), TM_JOBS (default nproc).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${TM_SANITIZE_BUILD_DIR:-$root/build-asan}"
jobs="${TM_JOBS:-$(nproc)}"
start=$SECONDS

printf '\n== sanitizer build: configuring %s\n' "$build"
# -O1 without -g, assertions on: quicker to build than RelWithDebInfo, and stack traces still name the functions.
# For line numbers, build RelWithDebInfo by hand (docs/TESTING.md).
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O1 -DCMAKE_C_FLAGS_RELEASE=-O1 \
  -DTISSUEMOSAIC_SANITIZE=ON -DTM_WITH_GUI=OFF > /dev/null
printf '\n== sanitizer build: building the subset'"'"'s driver with %s jobs\n' "$jobs"
# tm_sanitize_replays: the OpenIGTLink fuzz targets' corpora replayed once (Testing/SanitizeSubset.cmake).
cmake --build "$build" -j "$jobs" --target TissueMosaicSanitizeTests tm_sanitize_replays
built=$SECONDS

printf '\n== sanitizer build: running the subset (ctest -L sanitize)\n'
log="$build/Testing/run-sanitize-tests.log"
mkdir -p "$(dirname "$log")"
status=0
ctest --test-dir "$build" -L sanitize --output-on-failure -j "$jobs" "$@" 2>&1 | tee "$log" || status=$?
grep -E 'tests passed|tests failed out of' "$log" || echo "ctest printed no summary (see $log)"
echo "sanitizer step: build $((built - start)) s, tests $((SECONDS - built)) s"
if [ "$status" -ne 0 ]; then
  echo "SANITIZER RESULT: FAILED (ctest exit status $status; full log: $log)"
  exit "$status"
fi
echo "SANITIZER RESULT: PASSED"
