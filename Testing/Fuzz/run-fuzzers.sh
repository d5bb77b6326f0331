#!/usr/bin/env bash
# Fuzzes every reader of outside input for SECONDS_PER_TARGET seconds each (default 60), one target at a time
# (the fuzzers use one core), each on a copy of its seed corpus in Testing/Fuzz/corpus/<target>.
#   Testing/Fuzz/run-fuzzers.sh [SECONDS_PER_TARGET] [TARGET...]
# Configures and builds build-fuzz (clang, TISSUEMOSAIC_FUZZ=ON) when needed. Prints target, executions, crashes;
# crash, timeout, leak and out-of-memory inputs go to the artifacts folder it names (copy one into the target's
# corpus folder once the reader is fixed, so that the ctest `fuzz_<target>_corpus` keeps it tested).
# Exit status 1 when any target crashed. Environment: BUILD_DIR (build-fuzz), OUT_DIR (build-fuzz/fuzz-runs/<time>).
set -euo pipefail
seconds=${1:-60}
shift || true
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-fuzz}
out=${OUT_DIR:-$build/fuzz-runs/$(date -u +%Y%m%dT%H%M%SZ)}

if [[ ! -f $build/CMakeCache.txt ]]; then
  # -O1 without NDEBUG: faster to build than Release, and assertions stay on while fuzzing. OpenIGTLink (AUTO: when
  # installed) gives the network readers' targets, fuzz_igtl_client and fuzz_igtl_server.
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DTISSUEMOSAIC_FUZZ=ON -DTM_WITH_CUDA=OFF -DTM_WITH_IGTLINK=AUTO \
    -DTM_BUILD_TESTING=OFF -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O1 -DCMAKE_C_FLAGS_RELEASE=-O1 >/dev/null
elif grep -q '^TM_WITH_IGTLINK:STRING=OFF' "$build/CMakeCache.txt"; then
  cmake "$build" -DTM_WITH_IGTLINK=AUTO >/dev/null  # a build folder from before the OpenIGTLink targets
fi

targets=("$@")
named=$#
if ((${#targets[@]} == 0)); then
  for dir in "$root"/Testing/Fuzz/corpus/*/; do targets+=("$(basename "$dir")"); done
  cmake --build "$build" --target tm_fuzz_targets -j"${JOBS:-2}" >/dev/null
else
  # Only the targets asked for: fuzz_igtl_* need neither the engine nor VTK.
  cmake --build "$build" --target "${targets[@]}" -j"${JOBS:-2}" >/dev/null
fi
mkdir -p "$out"
# The readers' temporary files (FuzzFile.h) go here and are removed with it, even after a crash
# (in memory where /dev/shm exists: every execution writes one).
if [[ -w /dev/shm ]]; then scratch=$(mktemp -d -p /dev/shm); else scratch=$(mktemp -d); fi
trap 'rm -rf "$scratch"' EXIT

printf '%-24s %14s %8s\n' target executions crashes | tee "$out/summary.txt"
failed=0
total=0
for target in "${targets[@]}"; do
  binary=$build/Testing/Fuzz/$target
  if [[ ! -x $binary && $named == 0 && $target == fuzz_igtl_* ]]; then
    echo "$target: not built (no OpenIGTLink installed), skipped" >&2
    continue
  fi
  [[ -x $binary ]] || { echo "no fuzz target $binary" >&2; exit 2; }
  corpus=$out/corpus/$target
  artifacts=$out/artifacts/$target
  mkdir -p "$corpus" "$artifacts"
  cp "$root/Testing/Fuzz/corpus/$target"/* "$corpus"/
  # -fork=1: a crash, timeout or leak is recorded and the run goes on (-ignore_*), so one target's time is used
  # whole and every distinct crash is kept.
  set +e
  TMPDIR=$scratch LSAN_OPTIONS=suppressions=$root/Testing/Fuzz/lsan-suppressions.txt "$binary" "$corpus" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -fork=1 \
    -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -artifact_prefix="$artifacts/" -print_final_stats=1 \
    >"$out/$target.log" 2>&1
  set -e
  # With -fork, the parent's status lines "#N: cov: ..." count the executions of all its jobs.
  runs=$(grep -oE '^#[0-9]+: cov:' "$out/$target.log" | tr -dc '0-9\n' | sort -n | tail -1)
  runs=${runs:-0}
  crashes=$(find "$artifacts" -type f | wc -l)
  printf '%-24s %14s %8s\n' "$target" "$runs" "$crashes" | tee -a "$out/summary.txt"
  total=$((total + runs))
  ((crashes == 0)) || failed=1
done
printf '%-24s %14s\n' total "$total" | tee -a "$out/summary.txt"
echo "logs, corpora and crash artifacts: $out"
exit $failed
