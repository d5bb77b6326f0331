#!/usr/bin/env bash
# check-engine-layers-fails.sh CMAKE CHECK ENGINE WORK: the layering check must fail on a copy of the engine with an
# upward include (Core -> IO) and a Tracking <-> Stereo cycle added, naming both; prints PASS when it does.
set -uo pipefail
cmake=$1 check=$2 engine=$3 work=$4
rm -rf "$work" && mkdir -p "$work" && cp -r "$engine"/. "$work"/ || exit 1
echo '#include "IO/PointCloudPly.h"' >> "$work/Core/Error.h"
echo '#include "Stereo/StereoMatcher.h"' >> "$work/Tracking/FrameTracker.h"
output=$("$cmake" -DENGINE_DIR="$work" -P "$check" 2>&1); status=$?
echo "$output"
ok=1
[ "$status" -ne 0 ] || { echo "FAIL: the check passed a broken tree"; ok=0; }
grep -q 'Core/Error.h: #include "IO/PointCloudPly.h" (Core is below IO)' <<< "$output" ||
  { echo "FAIL: the upward include is not named"; ok=0; }
grep -q 'Tracking is on a cycle of folder includes' <<< "$output" || { echo "FAIL: the cycle is not named"; ok=0; }
rm -rf "$work"
[ $ok = 1 ] && echo "layering check on a broken tree: PASS"
[ $ok = 1 ]
