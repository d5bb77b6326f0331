#!/usr/bin/env bash
# hostile-server.sh CLI FAKE WORK CASE STATUS REGEX: `reconstruct --igtl-input 127.0.0.1:PORT --igtl-sbs Video` from
# tm-igtl-fake-plus sending the malformed message CASE and then WORK/scan's frames side by side. Passes when
# reconstruct exits with STATUS (never a crash) and its output matches REGEX.
set -uo pipefail
cli=$1 fake=$2 work=$3 case=$4 expected=$5 regex=$6
out=$work/hostile/$case
rm -rf "$out" && mkdir -p "$out"
"$fake" "$out/port" "$case" "$work/scan/left" "$work/scan/right" > "$out/server.txt" 2>&1 &
server=$!
for _ in $(seq 100); do [[ -s $out/port ]] && break; sleep 0.1; done
port=$(cat "$out/port")
"$cli" reconstruct --igtl-input "127.0.0.1:$port" --igtl-sbs Video --calib "$work/scan/rig.yml" --rectified \
       --device cpu --quiet --out "$out/model.ply" > "$out/reconstruct.txt" 2>&1
status=$?
wait "$server"
cat "$out/reconstruct.txt" "$out/server.txt"
if [[ $status != "$expected" ]]; then
  echo "FAIL: exit status $status, expected $expected"
  exit 1
fi
if ! grep -Eq -- "$regex" "$out/reconstruct.txt"; then
  echo "FAIL: the output does not match: $regex"
  exit 1
fi
echo "PASS"
