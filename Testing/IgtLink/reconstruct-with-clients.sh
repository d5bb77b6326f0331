#!/usr/bin/env bash
# reconstruct-with-clients.sh CLI CLIENT WORK PORT: reconstructs WORK/scan while two OpenIGTLink clients listen on
# PORT: one that checks everything against the files written, and one that reads slowly, leaves after 3 messages and
# comes back.
set -euo pipefail
cli=$1 client=$2 work=$3 port=$4
out=$work/igtl
rm -rf "$out" && mkdir -p "$out"
budget=20000
"$client" --port "$port" --connect-timeout 120 --expect-trajectory "$out/frames.txt" \
          --expect-model-ply "$out/model.ply" --model-budget "$budget" > "$out/checking-client.txt" 2>&1 &
checking=$!
# The second client connects after the first, so that the reconstruction (held for the first) starts before it.
(until grep -q "^connected" "$out/checking-client.txt" 2>/dev/null; do sleep 0.1; done
 exec "$client" --port "$port" --connect-timeout 120 --read-delay-ms 200 --disconnect-after 3 --reconnect \
          > "$out/nasty-client.txt" 2>&1) &
nasty=$!
"$cli" reconstruct --left-frames "$work/scan/left" --right-frames "$work/scan/right" --calib "$work/scan/rig.yml" \
       --rectified --device cpu --quiet --out "$out/model.ply" --frames-trajectory "$out/frames.txt" \
       --igtl-port "$port" --igtl-wait-client 30 --igtl-model-points "$budget" > "$out/reconstruct.txt" 2>&1 || {
  cat "$out/reconstruct.txt"; kill "$checking" "$nasty" 2>/dev/null; exit 1; }
cat "$out/reconstruct.txt"
status=0
wait "$checking" || status=1
wait "$nasty" || true
echo "--- slow client that left and came back:"; cat "$out/nasty-client.txt"
echo "--- checking client:"; sed 's/^PASS$/checking client: PASS/' "$out/checking-client.txt"
exit $status
