#!/usr/bin/env bash
# atomic-outputs.sh CLI WORK: a run that fails leaves existing outputs exactly as they were. Existing files are
# overwritten by runs that fail (a file-size limit as `ulimit -f` sets, a corrupt frame midway, an unwritable
# secondary output); each must exit non-zero (never by a signal), say why, and leave every file byte for byte as it
# was, with no temporary file behind. The last check is the control: the same run without the limit replaces them.
set -uo pipefail
cli=$1 work=$2
dir=$work/atomic
rm -rf "$dir" && mkdir -p "$dir/out"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
keep() { for name in "$@"; do printf 'the old %s\n' "$name" > "$dir/out/$name"; cp "$dir/out/$name" "$dir/$name.orig"; done; }
unchanged() {
  for name in "$@"; do cmp -s "$dir/out/$name" "$dir/$name.orig" || fail "$name was changed"; done
  local extra; extra=$(ls -A "$dir/out" | grep -v -x -F -f <(printf '%s\n' "$@") || true)
  [ -z "$extra" ] || fail "files left behind: $extra"
}
# expect_failure REGEX COMMAND...: non-zero status below 128 and stderr matching REGEX.
expect_failure() {
  local regex=$1; shift
  local stderr status
  stderr=$("$@" 2>&1 >/dev/null); status=$?
  echo "exit status $status: $stderr" | tail -n 3
  [ "$status" -ne 0 ] && [ "$status" -lt 128 ] || fail "exit status $status for: $*"
  grep -Eq -- "$regex" <<<"$stderr" || fail "stderr does not match /$regex/"
}
pair=(--left "$work/pair/left.png" --right "$work/pair/right.png" --device cpu --min-disparity 10 --max-disparity 40)
scan=(--left-frames "$work/scan/left" --right-frames "$work/scan/right" --calib "$work/scan/rig.yml" --rectified
      --device cpu --quiet)

echo "== stereo under a 8 KiB file-size limit: the 230 kB PFM cannot be written"
keep keep.pfm
expect_failure "cannot write PFM '.*keep.pfm': writing failed" bash -c 'ulimit -f 8; exec "$@"' - \
  "$cli" stereo "${pair[@]}" --out "$dir/out/keep.pfm"
unchanged keep.pfm

echo "== stereo: the cloud's folder is missing: refused before any work, --out untouched"
expect_failure "cannot write PLY \\(--cloud\\) '.*/missing/c.ply': the folder does not exist \\('.*/missing'\\)" \
  "$cli" stereo "${pair[@]}" --focal-px 300 --baseline-mm 5 --out "$dir/out/keep.pfm" --cloud "$dir/out/missing/c.ply"
unchanged keep.pfm

echo "== stereo: --out is a folder"
mkdir -p "$dir/folder.pfm"
expect_failure "cannot write PFM '.*folder.pfm': it is a folder" "$cli" stereo "${pair[@]}" --out "$dir/folder.pfm"

echo "== reconstruct under the limit: model and trajectories keep their old contents"
keep keep.pfm keep.ply keep.txt
expect_failure "cannot write .*keep.ply.*writing failed" bash -c 'ulimit -f 8; exec "$@"' - \
  "$cli" reconstruct "${scan[@]}" --max-frames 3 --out "$dir/out/keep.ply" --trajectory "$dir/out/keep.txt"
unchanged keep.pfm keep.ply keep.txt

echo "== reconstruct: an unwritable secondary output (timing JSON in a missing folder) is found before the scan"
expect_failure "cannot write timing JSON \\(--timing-json\\) '.*/missing/t.json': the folder does not exist" \
  "$cli" reconstruct "${scan[@]}" --out "$dir/out/keep.ply" --timing-json "$dir/out/missing/t.json"
unchanged keep.pfm keep.ply keep.txt

echo "== track: a corrupt frame midway fails the run; the old trajectory stays"
mkdir -p "$dir/frames" && cp -r "$work/scan/left" "$work/scan/right" "$dir/frames/"
corrupt=$(ls "$dir/frames/left" | sed -n 5p)
echo "not an image" > "$dir/frames/left/$corrupt"
expect_failure "cannot read image '.*$corrupt'" "$cli" track --left-frames "$dir/frames/left" \
  --right-frames "$dir/frames/right" --calib "$work/scan/rig.yml" --rectified --device cpu --quiet \
  --out "$dir/out/keep.txt"
unchanged keep.pfm keep.ply keep.txt

echo "== control: without the limit the same runs replace the files"
"$cli" stereo "${pair[@]}" --out "$dir/out/keep.pfm" > /dev/null || fail "stereo without a limit failed"
cmp -s "$dir/out/keep.pfm" "$dir/keep.pfm.orig" && fail "stereo did not replace keep.pfm"
head -c 2 "$dir/out/keep.pfm" | grep -q Pf || fail "keep.pfm is not a PFM"

[ "$failures" -eq 0 ] && echo "atomic outputs: PASS"
[ "$failures" -eq 0 ]
