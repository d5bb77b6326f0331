#!/usr/bin/env bash
# Runs on the GPU machine (the `device` tool) from the repository root, with a bundle made here by
#   ../shared/tools/device-bundle .device-bundle build/Testing/Engine/TissueMosaicCudaTests build/Module/Cli/tissuemosaic-bench
# It runs the CUDA-vs-CPU tests and the benchmarks (stereo, ORB, PnP, tracking three times, the 300-frame reconstruction;
# with LONG=1 also the 5-minute scan, 9000 frames rendered 100 at a time, about 7 minutes) and leaves logs and JSON in $OUT
# (or ./gpu-checks), one bench-*.json per run: Resources/scripts/benchmark-report.py turns them into docs/BENCHMARKS.md's tables.
set -uo pipefail
bundle=${BUNDLE:-.device-bundle}
out=${OUT:-gpu-checks}
bench="$bundle/run tissuemosaic-bench bench"
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm --format=csv | tee "$out/gpu.txt"
"$bundle/run" TissueMosaicCudaTests 2>&1 | tee "$out/cuda-tests.log" | grep -E "^\[  (PASSED|FAILED|SKIPPED)"
tests_status=${PIPESTATUS[0]}
$bench stereo --device cuda --repeats ${REPEATS:-200} 2>/dev/null | tee "$out/bench-stereo-cuda.json"
$bench stereo --device cpu --repeats 5 2>/dev/null > "$out/bench-stereo-cpu.json"
$bench stereo --device cuda --method ad-census 2>/dev/null > "$out/bench-stereo-adcensus-cuda.json"
$bench orb --device cuda 2>/dev/null > "$out/bench-orb-cuda.json"
$bench orb --device cpu 2>/dev/null > "$out/bench-orb-cpu.json"
$bench pnp --quick 2>/dev/null > "$out/bench-pnp-quick.json"
for run in 1 2 3; do $bench track --device cuda --frames 60 2>/dev/null | tee "$out/bench-track-cuda-$run.json"; done
$bench reconstruct --device cuda --frames 300 2>/dev/null | tee "$out/bench-reconstruct-cuda-300.json"
if [ "${LONG:-0}" = 1 ]; then
  $bench reconstruct --device cuda --frames 9000 --stream --chunk 100 --supersampling 1 2>/dev/null |
    tee "$out/bench-reconstruct-cuda-9000.json"
fi
echo "CUDA tests exit status: $tests_status"
exit "$tests_status"
