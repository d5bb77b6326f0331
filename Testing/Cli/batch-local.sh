#!/usr/bin/env bash
# batch-local.sh CLI WORK: `tissuemosaic batch` on this machine (issue 55's bar). Four studies, one a corrupt video,
# with --jobs 2; SIGTERM to the batch once a row is done and before all are: the batch and its rows stop at once, no
# row process or temporary file is left, the done rows keep their records. Run again, the batch does only the rows
# not done: 3 done, 1 failed with its reason, the summary says so. Each model equals, byte for byte, that of
# `tissuemosaic reconstruct` run alone with the row's options (and differs from another row's: the comparison can
# fail). A row whose own process is stopped by SIGTERM (reconstruct then writes what it did and exits 0) is failed.
set -uo pipefail
cli=$1 work=$2
source "$(dirname "$0")/batch-studies.sh"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# Rows 2 and 3 longer than row 1, so that the stop comes while a row still runs.
make_batch_studies "$cli" "$work" 10 30 30 || { echo "FAIL: cannot make the studies"; exit 1; }
manifest=$work/manifest.csv
done_rows() { ls "$work"/runs/*/done.json 2>/dev/null | wc -l; }

echo "== first run, stopped by SIGTERM once a row is done"
"$cli" batch "$manifest" --jobs 2 > "$work/first.out" 2> "$work/first.err" &
batch=$!
waited=0
until [ "$(done_rows)" -ge 1 ] || ! kill -0 "$batch" 2>/dev/null || [ $waited -gt 3000 ]; do
  sleep 0.1; waited=$((waited + 1))
done
kill -TERM "$batch"
wait "$batch"; status=$?
cat "$work/first.err"
done_at_stop=$(done_rows)
echo "exit status $status; rows done at the stop: $done_at_stop"
[ "$status" -eq 1 ] || fail "the stopped batch exited $status, expected 1"
grep -q "batch: stopped by SIGTERM: [1-9][0-9]* running rows were stopped" "$work/first.err" ||
  fail "the stopped batch did not say that it stopped running rows"
[ "$done_at_stop" -ge 1 ] && [ "$done_at_stop" -lt 3 ] ||
  fail "$done_at_stop rows done at the stop: it should come after the first and before the last"
sleep 0.5
if pgrep -f -- "$work/runs/" > /dev/null; then
  fail "row processes outlived the batch: $(pgrep -af -- "$work/runs/")"
fi
find "$work/runs" -name '.*.tmp-*' | grep -q . && fail "temporary files left: $(find "$work/runs" -name '.*.tmp-*')"
declare -A done_before
for record in "$work"/runs/*/done.json; do done_before[$record]=$(stat -c %Y.%s "$record"); done

echo "== second run: only what was left"
"$cli" batch "$manifest" --jobs 2 > "$work/second.out" 2> "$work/second.err"
status=$?
cat "$work/second.err" "$work/second.out"
[ "$status" -eq 1 ] || fail "the batch with a failing row exited $status, expected 1"
skipped=$(grep -c ": already done (" "$work/second.err")
started=$(grep -c ": started (log " "$work/second.err")
[ "$skipped" -eq "$done_at_stop" ] || fail "$skipped rows skipped, expected the $done_at_stop done at the stop"
[ "$started" -eq $((4 - done_at_stop)) ] || fail "$started rows started, expected $((4 - done_at_stop))"
for record in "${!done_before[@]}"; do
  [ "$(stat -c %Y.%s "$record")" = "${done_before[$record]}" ] || fail "$record was written again"
done
grep -q "^summary: 3 done, 1 failed, 0 not run, of 4 rows$" "$work/second.out" || fail "the summary line is wrong"
grep -Eq "^row 4 broken: failed \(exit status 1\): cannot open video 'broken.mp4': not a readable video" \
  "$work/second.out" || fail "the broken row's reason is missing"

echo "== the summary files"
csv=$work/manifest-summary.csv
cat "$csv"
[ "$(head -n 1 "$csv")" = "row,name,status,exit_status,frames,tracked,lost,key_frames,points,agreement,time_s,reason,out" ] ||
  fail "the CSV header is wrong"
for row in 1 2 3; do
  frames=$([ $row -eq 1 ] && echo 10 || echo 30)
  grep -Eq "^$row,study$row,done,0,$frames,[0-9]+,[0-9]+,[0-9]+,[1-9][0-9]*,0\.[0-9]{4},[0-9.]+,,$work/runs/study$row$" "$csv" ||
    fail "the CSV row of study$row is wrong"
done
grep -Eq "^4,broken,failed,1,,,,,,,[0-9.]+,cannot open video 'broken.mp4': not a readable video .*,$work/runs/broken$" "$csv" ||
  fail "the CSV row of the broken study is wrong"
grep -q '"done": 3, "failed": 1, "not_run": 0}' "$work/manifest-summary.json" || fail "the JSON counts are wrong"
grep -q '"name":"study2",.*"status":"done"' "$work/manifest-summary.json" || fail "the JSON rows are wrong"

echo "== the models equal those of reconstruct alone"
for row in 1 2 3; do
  (cd "$work" && "$cli" reconstruct --left-frames scan$row/left --right-frames scan$row/right --calib scan$row/rig.yml \
     --rectified --device cpu --quiet --out "$work/alone$row.ply" > /dev/null) || fail "reconstruct alone, study$row"
  cmp "$work/alone$row.ply" "$work/runs/study$row/model.ply" || fail "study$row: the batch's model differs"
done
cmp -s "$work/alone2.ply" "$work/runs/study3/model.ply" && fail "control: study2's model equals study3's"

echo "== a third run does nothing but the failed row"
"$cli" batch "$manifest" > "$work/third.out" 2> "$work/third.err"
[ "$(grep -c ': started (log ' "$work/third.err")" -eq 1 ] && grep -q "^row 4 broken: started" "$work/third.err" ||
  fail "the third run did not run the failed row alone"

echo "== a row whose reconstruct alone gets SIGTERM (as Slurm's time limit sends it) is partial, not done"
printf 'name,out,args\npartial,runs/partial,"--left-frames scan2/left --right-frames scan2/right --calib scan2/rig.yml --rectified --device cpu"\n' \
  > "$work/partial.csv"
"$cli" batch "$work/partial.csv" > "$work/partial.out" 2> "$work/partial.err" &
batch=$!
waited=0
until pgrep -f -- "$work/runs/partial/model.ply" > /dev/null || [ $waited -gt 600 ]; do sleep 0.05; waited=$((waited + 1)); done
# The signal once reconstruct's log shows a frame done ("N/30 frames: ..."): it handles SIGTERM by then. (A fixed
# second after the start could still find it reading its inputs on a loaded machine, which SIGTERM ends outright.)
waited=0
until grep -aEq "[0-9]+/[0-9]+ frames:" "$work/runs/partial/reconstruct.log" 2>/dev/null || [ $waited -gt 1200 ]; do
  sleep 0.05; waited=$((waited + 1))
done
row_pid=$(pgrep -f -- "$work/runs/partial/model.ply")
kill -TERM $row_pid
wait "$batch"; status=$?
cat "$work/partial.err"
[ "$status" -eq 1 ] || fail "the batch whose row was stopped exited $status, expected 1"
[ -e "$work/runs/partial/done.json" ] && fail "the stopped row has a done record"
grep -q "stopped by a signal before the end of its input" "$work/runs/partial/failed.json" ||
  fail "the stopped row's failure record does not say why"
grep -Eq '"exit_status": *143' "$work/runs/partial/failed.json" ||
  fail "the stopped row's failure record does not keep reconstruct's exit status 143 (128 + SIGTERM)"

[ "$failures" -eq 0 ] && echo "batch local: PASS"
[ "$failures" -eq 0 ]
