#!/usr/bin/env bash
# Runs on the GPU machine (the `device` tool) from the repository root, with a bundle made here by
#   ../shared/tools/device-bundle .device-bundle build/Testing/Engine/TissueMosaicCudaTests build/Module/Cli/tissuemosaic-bench \
#       [build-libsgm/libsgm-timing]
# (libsgm-timing: Testing/Device/libsgm-peer, the peer of bench stereo, timed in the same run when it is in the bundle).
# It runs the CUDA-vs-CPU tests and the benchmarks (stereo, ORB, PnP, tracking three times, the 300-frame reconstruction;
# with HD=1 also stereo and the reconstruction at 1280x1024 and 1920x1080 with 256 disparities; with LONG=1 the 5-minute
# scan, 9000 frames rendered 100 at a time, about 7 minutes; with SOAK=1 only the CUDA tests and the one-hour soak:
# 108000 frames (SOAK_FRAMES) of the 300-frame scan played forward and back, its memory at each quarter in
# soak.log) and leaves logs and JSON in ./gpu-checks (CHECKS_DIR), one
# bench-*.json per run: Resources/scripts/benchmark-report.py turns them into docs/BENCHMARKS.md's tables. Where $OUT is
# set (the device tool), everything is also packed into $OUT/gpu-checks.tgz: only a few files come back from there.
# The exit status is non-zero when a CUDA test failed, or skipped (check-cuda-log.sh): here every one must run.
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
bundle=${BUNDLE:-.device-bundle}
out=${CHECKS_DIR:-gpu-checks}
bench="$bundle/run tissuemosaic-bench bench"
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm --format=csv | tee "$out/gpu.txt"
"$bundle/run" TissueMosaicCudaTests 2>&1 | tee "$out/cuda-tests.log" | grep -E "^\[  (PASSED|FAILED|SKIPPED)"
tests_status=${PIPESTATUS[0]}
"$here/check-cuda-log.sh" "$out/cuda-tests.log" | tee "$out/cuda-tests-verdict.txt"
verdict_status=${PIPESTATUS[0]}
if [ "${SOAK:-0}" = 1 ]; then
  timeout ${SOAK_TIMEOUT_S:-560} $bench reconstruct --device cuda --frames 300 --supersampling 1 \
    --soak-frames ${SOAK_FRAMES:-108000} > "$out/bench-reconstruct-cuda-soak.json" \
    2> >(tr '\r' '\n' | grep -v "frame [0-9]*/" > "$out/soak.log")
  echo "soak exit status: $?" >> "$out/soak.log"
  sleep 1
  cat "$out/soak.log"
  head -c 1500 "$out/bench-reconstruct-cuda-soak.json"
else
$bench stereo --device cuda --repeats ${REPEATS:-200} 2>/dev/null | tee "$out/bench-stereo-cuda.json"
$bench stereo --device cpu --repeats 5 2>/dev/null > "$out/bench-stereo-cpu.json"
$bench stereo --device cuda --method ad-census 2>/dev/null > "$out/bench-stereo-adcensus-cuda.json"
$bench orb --device cuda 2>/dev/null > "$out/bench-orb-cuda.json"
$bench orb --device cpu 2>/dev/null > "$out/bench-orb-cpu.json"
$bench pnp --quick 2>/dev/null > "$out/bench-pnp-quick.json"
for run in 1 2 3; do $bench track --device cuda --frames 60 2>/dev/null | tee "$out/bench-track-cuda-$run.json"; done
$bench reconstruct --device cuda --frames 300 2>/dev/null | tee "$out/bench-reconstruct-cuda-300.json"
# The peer, 4-path (and 8-path), at the disparity counts libSGM takes (64, 128, 256) nearest ours.
libsgm=("$bundle/run" libsgm-timing)
if [ -x "$bundle/bin/libsgm-timing" ]; then
  "${libsgm[@]}" --width 960 --height 540 --disparities 128 --paths 4 > "$out/libsgm-960x540-128-4path.json"
  "${libsgm[@]}" --width 960 --height 540 --disparities 128 --paths 8 > "$out/libsgm-960x540-128-8path.json"
fi
if [ "${HD:-0}" = 1 ]; then
  for size in 1280x1024 1920x1080; do
    width=${size%x*} height=${size#*x}
    $bench stereo --device cuda --width "$width" --height "$height" --disparities 256 --repeats ${REPEATS:-200} \
      2>/dev/null | tee "$out/bench-stereo-cuda-$size-256.json"
    if [ -x "$bundle/bin/libsgm-timing" ]; then
      for paths in 4 8; do
        "${libsgm[@]}" --width "$width" --height "$height" --disparities 256 --paths $paths |
          tee "$out/libsgm-$size-256-${paths}path.json"
      done
    fi
    $bench track --device cuda --width "$width" --height "$height" --disparities 256 --frames 60 2>/dev/null \
      > "$out/bench-track-cuda-$size-256.json"
    $bench reconstruct --device cuda --width "$width" --height "$height" --disparities 256 --frames ${HD_FRAMES:-120} \
      2>/dev/null | tee "$out/bench-reconstruct-cuda-$size-256.json"
  done
fi
fi
if [ "${LONG:-0}" = 1 ]; then
  $bench reconstruct --device cuda --frames 9000 --stream --chunk 100 --supersampling 1 2>/dev/null |
    tee "$out/bench-reconstruct-cuda-9000.json"
fi
echo "CUDA tests exit status: $tests_status; verdict: $(tail -n 1 "$out/cuda-tests-verdict.txt")" | tee "$out/status.txt"
if [ -n "${OUT:-}" ] && [ "$out" != "$OUT" ]; then tar -czf "$OUT/gpu-checks.tgz" -C "$out" .; fi
[ "$tests_status" -eq 0 ] && [ "$verdict_status" -eq 0 ]
