#!/usr/bin/env bash
# batch-studies.sh CLI DIR FRAMES...: the batch tests' studies in DIR: one small synthetic scan per FRAMES value
# (seeds 1, 2, ...; 320x240), a corrupt video, and manifest.csv with a row per scan (study1, study2, ...) and the
# broken study last, every row on the CPU. Sourced by batch-local.sh and batch-slurm.sh.
make_batch_studies() {
  local cli=$1 dir=$2; shift 2
  rm -rf "$dir" && mkdir -p "$dir" || return 1
  printf 'name,out,args\n' > "$dir/manifest.csv"
  local seed=0 frames
  for frames in "$@"; do
    seed=$((seed + 1))
    "$cli" synth scan --out "$dir/scan$seed" --frames "$frames" --width 320 --height 240 --seed "$seed" > /dev/null 2>&1 ||
      return 1
    printf 'study%d,runs/study%d,"--left-frames scan%d/left --right-frames scan%d/right --calib scan%d/rig.yml --rectified --device cpu"\n' \
      "$seed" "$seed" "$seed" "$seed" "$seed" >> "$dir/manifest.csv"
  done
  # Not a video: bytes no demuxer reads.
  head -c 65536 /dev/zero | tr '\0' 'x' > "$dir/broken.mp4"
  printf 'broken,runs/broken,"--video broken.mp4 --focal-px 300 --baseline-mm 5 --device cpu"\n' >> "$dir/manifest.csv"
}
