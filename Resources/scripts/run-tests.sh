#!/usr/bin/env bash
# Set up and build, then run every test (ctest). GUI tests need an X display: without DISPLAY the run goes
# under xvfb-run. CUDA tests (label "cuda") skip with a message where no GPU exists. Exits non-zero on failure.
# Extra arguments go to ctest, e.g. `run-tests.sh -L logic`.
# A whole run (no arguments) then runs the sanitizer step, run-sanitize-tests.sh: an ASan + UBSan build of the
# readers of outside input and their tests (label "sanitize", docs/TESTING.md), about 3 minutes from cold on 2 cores.
# TM_SANITIZE=0 leaves it out.
set -euo pipefail
# shellcheck source=SCRIPTDIR/setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
tm_setup

log="$TM_BUILD_DIR/Testing/run-tests.log"
mkdir -p "$(dirname "$log")"
ctest_command=(ctest --test-dir "$TM_BUILD_DIR" --output-on-failure -j "$TM_JOBS" "$@")
if [ -z "${DISPLAY:-}" ]; then
  ctest_command=(xvfb-run -a -s "-screen 0 1280x1024x24" "${ctest_command[@]}")
fi

tm_log "running: ${ctest_command[*]}"
status=0
"${ctest_command[@]}" 2>&1 | tee "$log" || status=$?

tm_log "summary"
grep -E 'tests passed|tests failed out of' "$log" || echo "ctest printed no summary (see $log)"
skipped="$(grep -c -F '***Skipped' "$log" || true)"
echo "skipped: $skipped (CUDA tests skip where no GPU exists; run them with: ctest --test-dir $TM_BUILD_DIR -L cuda)"
# Without a GPU exactly the CUDA tests skip, and nothing else may (docs/TESTING.md): a whole run checks the count.
if [ $# -eq 0 ] && ! nvidia-smi -L > /dev/null 2>&1; then
  cuda_tests="$(ctest --test-dir "$TM_BUILD_DIR" -N -L cuda | grep -c 'Test *#' || true)"
  # The Slurm test skips, with its reason, where the daemons cannot start (CI sets TM_REQUIRE_SLURM=1: it fails there).
  slurm_skipped="$(grep -F '***Skipped' "$log" | grep -c 'cli\.batch\.slurm ' || true)"
  [ "$slurm_skipped" -eq 0 ] || echo "the Slurm test skipped: its daemons cannot start here (see its output above)"
  if [ "$skipped" -ne $((cuda_tests + slurm_skipped)) ]; then
    echo "skips: $skipped, but this machine has no GPU and $cuda_tests CUDA tests: a test other than the CUDA ones skipped"
    [ "$status" -ne 0 ] || status=1
  fi
fi
if [ $# -eq 0 ] && [ "${TM_SANITIZE:-1}" != 0 ]; then
  sanitize_status=0
  bash "$TM_REPO_ROOT/Resources/scripts/run-sanitize-tests.sh" || sanitize_status=$?
  [ "$status" -ne 0 ] || status=$sanitize_status
else
  echo "sanitizer step not run (a whole run without TM_SANITIZE=0 runs it: docs/TESTING.md)"
fi
if [ "$status" -ne 0 ]; then
  echo "RESULT: FAILED (exit status $status; full log: $log, and the sanitizer step's above)"
  exit "$status"
fi
echo "RESULT: PASSED"
