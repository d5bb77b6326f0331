#!/usr/bin/env bash
# stop-on-signal.sh CLI SCAN OUT: track and reconstruct over the frame folders of the synthetic scan SCAN, each sent
# SIGTERM once its progress line shows frame 3: each must exit 143 (128 + SIGTERM, as a shell reports a program a
# signal ended: the run is not whole), say "stopped by a signal after N frames" with N < all and why it exits so on
# stderr, and write complete outputs of the frames it did (the trajectory marked incomplete; the model a whole PLY).
set -uo pipefail
cli=$1 scan=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
all=$(ls "$scan/left" | wc -l)
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
frames=(--left-frames "$scan/left" --right-frames "$scan/right" --calib "$scan/rig.yml" --rectified --device cpu)
# run_and_stop NAME COMMAND...: runs COMMAND, its stderr to OUT/NAME.err, and sends SIGTERM when frame 3 shows.
run_and_stop() {
  local name=$1; shift
  "$@" > "$out/$name.out" 2> "$out/$name.err" &
  local pid=$! waited=0
  until grep -Eq "frame 3/|3/$all" "$out/$name.err" 2>/dev/null || ! kill -0 "$pid" 2>/dev/null || [ $waited -gt 1200 ]; do
    sleep 0.05; waited=$((waited + 1))
  done
  kill -TERM "$pid" 2>/dev/null
  wait "$pid"; status=$?
  echo "== $name: exit status $status"; cat "$out/$name.out"
  [ "$status" -eq 143 ] || fail "$name: exit status $status, expected 143 (128 + SIGTERM)"
  grep -Eq "^tissuemosaic $name: stopped by signal 15 \(Terminated\) after [0-9]+ frames: the outputs hold those frames only$" \
    "$out/$name.err" || fail "$name: stderr does not say it stopped on SIGTERM"
  stopped=$(sed -n 's/.*stopped by a signal after \([0-9]*\) frames.*/\1/p' "$out/$name.out" | head -n 1)
  [ -n "$stopped" ] && [ "$stopped" -ge 3 ] && [ "$stopped" -lt "$all" ] ||
    fail "$name: no 'stopped by a signal after N frames' with 3 <= N < $all"
}

run_and_stop track "$cli" track "${frames[@]}" --out "$out/trajectory.txt"
poses=$(grep -cv '^#' "$out/trajectory.txt" 2>/dev/null || echo 0)
[ "$poses" -ge 3 ] && [ "$poses" -lt "$all" ] || fail "track: $poses poses written, expected 3 <= n < $all"
tail -n 1 "$out/trajectory.txt" | grep -q "# stopped by a signal after [0-9]* frames: the trajectory is incomplete" ||
  fail "track: the trajectory does not end with the incomplete mark"

run_and_stop reconstruct "$cli" reconstruct "${frames[@]}" --out "$out/model.ply" --frames-trajectory "$out/frames.txt"
head -n 1 "$out/model.ply" | grep -qx ply || fail "reconstruct: no model written"
# A whole binary PLY: header, then exactly count x (the properties' bytes).
count=$(sed -n 's/^element vertex \([0-9]*\)$/\1/p' "$out/model.ply" | head -n 1)
vertexBytes=$(sed -n '1,/^end_header/p' "$out/model.ply" | awk '/^property float/ {n += 4} /^property uchar/ {n += 1} END {print n}')
header=$(grep -abo "end_header" "$out/model.ply" | head -n 1 | cut -d: -f1)
size=$(stat -c %s "$out/model.ply")
[ -n "$count" ] && [ "$size" -eq $((header + 11 + count * vertexBytes)) ] ||
  fail "reconstruct: the PLY is not whole ($size bytes, $count points of $vertexBytes bytes)"
ls -A "$out" | grep -q '\.tmp-' && fail "temporary files left behind"

[ "$failures" -eq 0 ] && echo "stop on signal: PASS"
[ "$failures" -eq 0 ]
