#!/usr/bin/env bash
# Runs on the GPU machine (the `device` tool) from the repository root, with a bundle made here by
#   ../shared/tools/device-bundle .device-bundle build/Testing/Engine/TissueMosaicCudaTests build/Module/Cli/tissuemosaic-bench
# It runs the CUDA-vs-CPU tests and the stereo benchmark, and leaves logs and JSON in $OUT (or ./gpu-checks).
set -uo pipefail
bundle=${BUNDLE:-.device-bundle}
out=${OUT:-gpu-checks}
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm --format=csv | tee "$out/gpu.txt"
"$bundle/run" TissueMosaicCudaTests 2>&1 | tee "$out/cuda-tests.log"
tests_status=${PIPESTATUS[0]}
"$bundle/run" tissuemosaic-bench bench stereo --device cuda --repeats ${REPEATS:-200} 2>/dev/null | tee "$out/bench-stereo-cuda.json"
"$bundle/run" tissuemosaic-bench bench stereo --device cpu --repeats 5 2>/dev/null | tee "$out/bench-stereo-cpu.json"
echo "CUDA tests exit status: $tests_status"
exit "$tests_status"
