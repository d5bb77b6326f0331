#!/usr/bin/env bash
# batch-slurm.sh CLI WORK: `tissuemosaic batch --slurm` against a real Slurm (Debian's slurm-wlm and munge) that this
# script starts on this machine: munged, slurmctld and slurmd with a configuration of one node written into a
# temporary folder, stopped at the end whatever happens. Three synthetic studies and a broken one go as one job
# array: 3 done, 1 failed with its reason, the summary says so; a resubmission asks for the failed row alone and
# leaves the others as they were. Exit 77 (a skip) only where the daemons cannot be installed or started, with
# the reason; with TM_REQUIRE_SLURM=1 (CI) that is a failure instead.
set -uo pipefail
cli=$1 work=$2
source "$(dirname "$0")/batch-studies.sh"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cannot_run() {
  if [ "${TM_REQUIRE_SLURM:-0}" = 1 ]; then echo "FAIL: $* (TM_REQUIRE_SLURM=1: this machine must run Slurm)"; exit 1; fi
  echo "SKIP: $*"; exit 77
}
for tool in munged mungekey slurmctld slurmd sbatch squeue sinfo scontrol; do
  command -v "$tool" > /dev/null || cannot_run "$tool is not installed (Debian: apt-get install slurm-wlm munge)"
done

# A short folder: munge's socket path must fit in 108 bytes.
temp=$(mktemp -d /tmp/tm-slurm.XXXXXX)
export SLURM_CONF=$temp/slurm.conf
stop_daemons() {
  timeout 10 scontrol shutdown > /dev/null 2>&1
  local pidfile pid
  for pidfile in "$temp/slurmd.pid" "$temp/slurmctld.pid" "$temp/munged.pid"; do
    pid=$(cat "$pidfile" 2>/dev/null) || continue
    kill "$pid" 2>/dev/null
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null
  done
  rm -rf "$temp"
}
trap stop_daemons EXIT

# Two free ports: nothing answers on them.
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
port=$((20000 + RANDOM % 20000))
until port_free "$port" && port_free $((port + 1)); do port=$((port + 2)); done
user=$(id -un)
host=$(hostname -s)
mkdir -p "$temp/state" "$temp/spool" && chmod 700 "$temp"
cat > "$SLURM_CONF" <<CONF
ClusterName=tissuemosaic-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$temp/munge.socket
CredType=cred/munge
StateSaveLocation=$temp/state
SlurmdSpoolDir=$temp/spool
SlurmctldPidFile=$temp/slurmctld.pid
SlurmdPidFile=$temp/slurmd.pid
SlurmctldLogFile=$temp/slurmctld.log
SlurmdLogFile=$temp/slurmd.log
PlugStackConfig=$temp/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=studies Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
: > "$temp/plugstack.conf"
mungekey --create --keyfile="$temp/munge.key" > /dev/null 2>&1 && chmod 400 "$temp/munge.key" ||
  cannot_run "mungekey cannot make a key"
munged --key-file="$temp/munge.key" --socket="$temp/munge.socket" --pid-file="$temp/munged.pid" \
  --log-file="$temp/munged.log" --seed-file="$temp/munged.seed" --force > "$temp/munged.out" 2>&1 ||
  cannot_run "munged does not start: $(cat "$temp/munged.out" "$temp/munged.log" 2>/dev/null | tail -n 3)"
timeout 30 slurmctld -c -i -f "$SLURM_CONF" > "$temp/slurmctld.out" 2>&1 ||
  cannot_run "slurmctld does not start: $(tail -n 3 "$temp/slurmctld.out" "$temp/slurmctld.log" 2>/dev/null)"
timeout 30 slurmd -f "$SLURM_CONF" > "$temp/slurmd.out" 2>&1 ||
  cannot_run "slurmd does not start: $(tail -n 3 "$temp/slurmd.out" "$temp/slurmd.log" 2>/dev/null)"
waited=0
until timeout 5 sinfo -h -o %t 2>/dev/null | grep -qx idle; do
  [ $waited -lt 60 ] || cannot_run "the Slurm node never became idle: $(tail -n 3 "$temp/slurmd.log" "$temp/slurmctld.log")"
  sleep 0.5; waited=$((waited + 1))
done
echo "Slurm $(sinfo -V) up: controller on port $port, node $host, configuration $SLURM_CONF"

make_batch_studies "$cli" "$work" 10 10 10 || { echo "FAIL: cannot make the studies"; exit 1; }
manifest=$work/manifest.csv
# wait_for_array JOB: until the array has left the queue (at most 5 minutes).
wait_for_array() {
  local waited=0
  while [ -n "$(timeout 5 squeue -h -j "$1" 2>/dev/null)" ]; do
    [ $waited -lt 600 ] || { fail "job array $1 still queued after 5 minutes"; return 1; }
    sleep 0.5; waited=$((waited + 1))
  done
}
# submit: the batch's --slurm; echoes the job id.
submit() {
  timeout 60 "$cli" batch "$manifest" --slurm --time 10:00 > "$work/submit.out" 2>&1 ||
    { cat "$work/submit.out"; fail "--slurm failed"; return 1; }
  cat "$work/submit.out" >&2
  sed -n 's/^submitted job array \([0-9]*\): .*/\1/p' "$work/submit.out"
}

echo "== the array of four rows"
job=$(submit) && [ -n "$job" ] || { fail "no job id"; exit 1; }
grep -q "^submitted job array $job: 4 tasks (rows 1-4)" "$work/submit.out" || fail "the array is not rows 1-4"
wait_for_array "$job"
ls "$work/manifest-slurm/slurm-${job}_"{1,2,3,4}.out > /dev/null || fail "a task's log is missing"
timeout 60 "$cli" batch "$manifest" --summary > "$work/summary.out" 2> "$work/summary.err"
status=$?
cat "$work/summary.out" "$work/summary.err"
[ "$status" -eq 1 ] || fail "--summary with a failed row exited $status, expected 1"
grep -q "^summary: 3 done, 1 failed, 0 not run, of 4 rows$" "$work/summary.out" || fail "the summary line is wrong"
grep -Eq "^row 4 broken: failed \(exit status 1\): cannot open video 'broken.mp4': not a readable video" \
  "$work/summary.out" || fail "the broken row's reason is missing"
for row in 1 2 3; do
  grep -Eq "^$row,study$row,done,0,10,[0-9]+,[0-9]+,[0-9]+,[1-9][0-9]*,0\.[0-9]{4},[0-9.]+,,$work/runs/study$row$" \
    "$work/manifest-summary.csv" || fail "the summary CSV's row $row is wrong"
done
grep -q '"done": 3, "failed": 1, "not_run": 0}' "$work/manifest-summary.json" || fail "the JSON counts are wrong"
declare -A before
for row in study1 study2 study3; do before[$row]=$(stat -c %Y.%s "$work/runs/$row/done.json" "$work/runs/$row/model.ply"); done

echo "== the resubmission: the failed row alone"
job2=$(submit) && [ -n "$job2" ] || { fail "no job id on resubmission"; exit 1; }
grep -q "^submitted job array $job2: 1 tasks (rows 4)" "$work/submit.out" || fail "the resubmission is not row 4 alone"
grep -qx "#SBATCH --array=4" "$work/manifest-slurm/array.sbatch" || fail "the script's array is not row 4"
wait_for_array "$job2"
[ -s "$work/manifest-slurm/slurm-${job2}_4.out" ] || fail "the resubmitted task left no log"
ls "$work/manifest-slurm/slurm-${job2}_"[123].out 2> /dev/null && fail "the resubmission ran a done row"
for row in study1 study2 study3; do
  [ "$(stat -c %Y.%s "$work/runs/$row/done.json" "$work/runs/$row/model.ply")" = "${before[$row]}" ] ||
    fail "$row was written again"
done
timeout 60 "$cli" batch "$manifest" --summary > "$work/summary2.out" 2>&1
grep -q "^summary: 3 done, 1 failed, 0 not run, of 4 rows$" "$work/summary2.out" || fail "the second summary is wrong"

[ "$failures" -eq 0 ] && echo "batch slurm: PASS"
[ "$failures" -eq 0 ]
