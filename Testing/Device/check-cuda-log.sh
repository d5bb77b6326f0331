#!/usr/bin/env bash
# check-cuda-log.sh LOG: the verdict on a TissueMosaicCudaTests run on the GPU machine (run-gpu-checks.sh). There
# every CUDA test must run: a skip means the GPU was not used, so it fails the run like a failed test does, and so
# does a log in which no test passed at all. Prints the verdict; exit status 0 only for a clean run.
set -u
log=${1:?usage: check-cuda-log.sh LOG}
[ -r "$log" ] || { echo "check-cuda-log: cannot read '$log'"; exit 1; }
passed=$(sed -n 's/^\[  PASSED  \] \([0-9][0-9]*\) tests\{0,1\}\..*/\1/p' "$log" | tail -n 1)
skipped=$(grep -c '^\[  SKIPPED \] [A-Za-z_][A-Za-z0-9_]*\.[A-Za-z0-9_]* ' "$log")
failed=$(grep -c '^\[  FAILED  \] [A-Za-z_][A-Za-z0-9_]*\.[A-Za-z0-9_]* ' "$log")
echo "CUDA tests: ${passed:-0} passed, $skipped skipped, $failed failed"
if [ "$failed" -gt 0 ]; then echo "FAIL: CUDA tests failed"; exit 1; fi
if [ "$skipped" -gt 0 ]; then echo "FAIL: CUDA tests skipped: on the GPU machine every CUDA test must run"; exit 1; fi
if [ "${passed:-0}" -eq 0 ]; then echo "FAIL: no CUDA test passed"; exit 1; fi
echo "ok: every CUDA test ran and passed"
