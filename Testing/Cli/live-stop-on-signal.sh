#!/usr/bin/env bash
# live-stop-on-signal.sh CLI SCAN OUT SECONDS: reconstructs the synthetic scan SCAN (tissuemosaic synth scan) played
# live at 30 fps through a GStreamer pipeline (both eyes composited side by side, looping), sends SIGINT after
# SECONDS, and checks a clean stop: exit status 0, the model and trajectory written, the dropped frames reported.
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
awk -v q="$((seconds / 4))" '$1 >= q {if (min == "" || $2 < min) min = $2; if ($2 > max) max = $2}
     END {printf "resident memory after %.1f s: %.0f to %.0f MiB\n", q, min / 1024, max / 1024}' "$out/rss.txt"
ok=1
[ "$status" = 0 ] || { echo "FAIL: exit status $status"; ok=0; }
[ -s "$out/model.ply" ] || { echo "FAIL: no model written"; ok=0; }
grep -q "stopped by a signal" "$out/reconstruct.txt" || { echo "FAIL: the stop was not reported"; ok=0; }
grep -Eq "live source: [0-9]+ frames reconstructed, [1-9][0-9]* dropped" "$out/reconstruct.txt" ||
  { echo "FAIL: no dropped frames reported"; ok=0; }
[ $ok = 1 ] && echo "live stop: PASS"
[ $ok = 1 ]
