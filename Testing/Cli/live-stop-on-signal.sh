#!/usr/bin/env bash
# live-stop-on-signal.sh CLI SCAN OUT SECONDS: reconstructs the synthetic scan SCAN (tissuemosaic synth scan) played
# live at 30 fps through a GStreamer pipeline (both eyes composited side by side, looping), sends SIGINT after
# SECONDS, and checks a clean stop: exit status 130 (128 + SIGINT: the run is not whole), the model and trajectory
# written, the dropped frames reported.
# Samples the resident memory every 0.5 s (OUT/rss.txt) and prints its range after the first quarter of the run.
set -uo pipefail
cli=$1 scan=$2 out=$3 seconds=$4
rm -rf "$out" && mkdir -p "$out"
width=$(sed -n 's/^imageSize: \[ *\([0-9]*\),.*/\1/p' "$scan/rig.yml")  # synth scan writes imageSize
last=$(($(ls "$scan/left" | wc -l) - 1))
eye() { echo "multifilesrc location=$scan/$1/%06d.png index=0 stop-index=$last loop=true caps=image/png,framerate=30/1 ! pngdec ! c."; }
pipeline="compositor name=c sink_1::xpos=$width ! videoconvert ! video/x-raw,format=BGR ! appsink $(eye left) $(eye right)"
"$cli" reconstruct --video "$pipeline" --calib "$scan/rig.yml" --rectified --device cpu --quiet \
       --out "$out/model.ply" --frames-trajectory "$out/frames.txt" --timing-json "$out/timing.json" \
       > "$out/reconstruct.txt" 2>&1 &
pid=$!
start=$(date +%s%3N)
while kill -0 "$pid" 2>/dev/null; do
  elapsedMs=$(($(date +%s%3N) - start))
  awk -v t="$elapsedMs" '/VmRSS/ {print t / 1000, $2}' "/proc/$pid/status" 2>/dev/null >> "$out/rss.txt"
  if [ "$elapsedMs" -gt $((seconds * 1000)) ] && [ ! -e "$out/signalled" ]; then
    kill -INT "$pid"; touch "$out/signalled"
  fi
  sleep 0.5
done
wait "$pid"; status=$?
cat "$out/reconstruct.txt"
echo "exit status $status"
# Memory over the run: the resident size at each quarter of it (flat once the model stops growing much).
awk -v s="$seconds" '{t[NR] = $1; m[NR] = $2} END {
  printf "resident memory (MiB) at"; for (q = 1; q <= 4; ++q) { best = 0
    for (i = 1; i <= NR; ++i) if (t[i] <= q * s / 4) best = i
    if (best) printf " %.0f s: %.0f", t[best], m[best] / 1024 }
  printf "\n" }' "$out/rss.txt"
ok=1
[ "$status" = 130 ] || { echo "FAIL: exit status $status, expected 130 (128 + SIGINT)"; ok=0; }
grep -q "stopped by signal 2 (Interrupt)" "$out/reconstruct.txt" || { echo "FAIL: stderr does not name SIGINT"; ok=0; }
[ -s "$out/model.ply" ] || { echo "FAIL: no model written"; ok=0; }
grep -q "stopped by a signal" "$out/reconstruct.txt" || { echo "FAIL: the stop was not reported"; ok=0; }
grep -Eq "live source: [0-9]+ frames reconstructed, [1-9][0-9]* dropped" "$out/reconstruct.txt" ||
  { echo "FAIL: no dropped frames reported"; ok=0; }
[ $ok = 1 ] && echo "live stop: PASS"
[ $ok = 1 ]
