#!/usr/bin/env bash
# The main job on the bundled default input: set up and build, generate a synthetic scanning video of a liver-like
# surface with exact ground truth (made on the fly), reconstruct it with the whole pipeline (stereo, tracking,
# key-frame refinement, TSDF fusion), and report the model's accuracy against the true surface and trajectory.
#
# Environment (optional): TM_DEVICE cpu|cuda|auto (default auto), TM_DEMO_FRAMES (default 300),
# TM_DEMO_WIDTH / TM_DEMO_HEIGHT (default 960x540), plus setup.sh's TM_BUILD_DIR, TM_CMAKE_ARGS, TM_JOBS.
set -euo pipefail
# shellcheck source=SCRIPTDIR/setup.sh
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
tm_setup

tool="$TM_BUILD_DIR/Module/Cli/tissuemosaic"
demo="$TM_BUILD_DIR/demo"
scan="$demo/scan"
device="${TM_DEVICE:-auto}"
frames="${TM_DEMO_FRAMES:-300}"
width="${TM_DEMO_WIDTH:-960}"
height="${TM_DEMO_HEIGHT:-540}"
mkdir -p "$demo"

tm_log "generating a synthetic scan ($frames frames, ${width}x${height}) in $scan"
rm -rf "$scan"
"$tool" synth scan --out "$scan" --frames "$frames" --width "$width" --height "$height"

tm_log "reconstructing the scan (device $device)"
# The frames are rectified as rig.yml's rectification makes them; the first pose is the ground truth's first, so
# the model lies in the ground truth's world frame (so eval needs no alignment).
"$tool" reconstruct --left-frames "$scan/left" --right-frames "$scan/right" --calib "$scan/rig.yml" --rectified \
  --start-tum "$scan/groundtruth/trajectory.txt" --device "$device" \
  --out "$demo/model.ply" --trajectory "$demo/keyframes.txt" --frames-trajectory "$demo/frames.txt" \
  --timing-json "$demo/timing.json"

tm_log "accuracy against the ground truth (model to true surface, coverage, key-frame trajectory)"
"$tool" eval --model "$demo/model.ply" --reference "$scan/groundtruth/surface.ply" \
  --trajectory "$demo/keyframes.txt" --reference-trajectory "$scan/groundtruth/trajectory.txt" \
  --trajectory-alignment none --json \
  | tee "$demo/accuracy.json"

tm_log "demo done: model $demo/model.ply, key frames $demo/keyframes.txt, accuracy $demo/accuracy.json"
