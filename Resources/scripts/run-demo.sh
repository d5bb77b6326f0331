#!/usr/bin/env bash
# The main job on the bundled default input: set up and build, generate a synthetic stereo pair with exact
# ground truth, reconstruct it (disparity + coloured point cloud), and report accuracy against the ground truth.
set -euo pipefail
# shellcheck source=SCRIPTDIR/setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
tm_setup

tool="$TM_BUILD_DIR/Module/Cli/tissuemosaic"
demo="$TM_BUILD_DIR/demo"
device="${TM_DEVICE:-auto}"

tm_log "generating a synthetic stereo pair in $demo"
"$tool" synth pair --out "$demo"

tm_log "stereo reconstruction (device $device), accuracy against the ground truth $demo/disparity.pfm"
# rig.yml calibrates the unrectified (raw) pair, so the raw images go in and the tool rectifies them; the
# ground truth is in the rectified left view. The estimate gets its own file: disparity.pfm is the truth.
"$tool" stereo --left "$demo/left_raw.png" --right "$demo/right_raw.png" --calib "$demo/rig.yml" \
  --out "$demo/estimate.pfm" --cloud "$demo/cloud.ply" --device "$device" \
  --ground-truth "$demo/disparity.pfm"

tm_log "demo done: disparity $demo/estimate.pfm, point cloud $demo/cloud.ply"
