#!/bin/sh
# The Slurm recipe (scripts/slurm/) on a real one-node cluster: munged,
# slurmctld and slurmd started here, on localhost, from a configuration
# this script writes (its own key, socket, ports, spool and state
# folders, so nothing of the machine's own setup is used or touched). It
# submits a frame as a tile array plus the dependent assemble job, and an
# animation as a frame array, waits for them, and compares the results
# with single-process renders: byte for byte. The daemons are stopped at
# the end. Skips (with the daemons' own words) only when they cannot be
# started here. Ends with "N passed, N failed[, N skipped]".
#
#   sh tests/slurm.sh SUMI

SUMI=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${OUT:-$ROOT/build/test-out/slurm}
WAIT=${SLURM_TEST_WAIT:-600}   # seconds the jobs may take, all told
passed=0; failed=0

ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL slurm/$1"; }
skip() {
  echo "skip slurm: $1"
  [ -n "${2:-}" ] && [ -f "$2" ] && sed 's/^/  /' "$2" | tail -5
  echo "$passed passed, $failed failed, 1 skipped"
  exit 0
}

for cmd in munged slurmctld slurmd sbatch squeue scontrol; do
  command -v $cmd >/dev/null || { echo "FAIL slurm: no $cmd (make test-slurm installs slurm-wlm and munge)"; echo "0 passed, 1 failed"; exit 1; }
done

# A fresh folder for the cluster (its socket must be reachable by all,
# and writable by us alone).
rm -rf "$OUT"; mkdir -p "$OUT/spool" "$OUT/state" "$OUT/jobs"; chmod 755 "$OUT"
cd "$OUT" || exit 1

# Three free TCP ports on localhost: slurmctld's, slurmd's, srun's range.
ports=$(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(" ".join(str(x.getsockname()[1]) for x in s))')
ctld_port=${ports% *}; d_port=${ports#* }

stop() {
  for d in slurmd slurmctld munged; do
    [ -f "$OUT/$d.pid" ] && kill "$(cat "$OUT/$d.pid")" 2>/dev/null
  done
  sleep 1
  for d in slurmd slurmctld munged; do
    [ -f "$OUT/$d.pid" ] && kill -9 "$(cat "$OUT/$d.pid")" 2>/dev/null
  done
}
trap stop EXIT

# munge: our own key and socket.
dd if=/dev/urandom of=munge.key bs=1024 count=1 2>/dev/null; chmod 400 munge.key
munged --key-file="$OUT/munge.key" --socket="$OUT/munge.socket" --pid-file="$OUT/munged.pid" \
  --log-file="$OUT/munged.log" --seed-file="$OUT/munged.seed" >"$OUT/munged.out" 2>&1 ||
  skip "munged does not start here" "$OUT/munged.out"

cpus=$(nproc)
user=$(id -un)
cat >slurm.conf <<CONF
# A one-node cluster on this machine, for tests/slurm.sh.
ClusterName=sumitest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$OUT/munge.socket
CredType=cred/munge
StateSaveLocation=$OUT/state
SlurmdSpoolDir=$OUT/spool
SlurmctldPidFile=$OUT/slurmctld.pid
SlurmdPidFile=$OUT/slurmd.pid
SlurmctldLogFile=$OUT/slurmctld.log
SlurmdLogFile=$OUT/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=600
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=sumitest NodeHostname=$(hostname -s) NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=1000 State=UNKNOWN
PartitionName=test Nodes=sumitest Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$OUT/slurm.conf"

slurmctld -i >"$OUT/slurmctld.out" 2>&1 || skip "slurmctld does not start here" "$OUT/slurmctld.log"
slurmd -N sumitest >"$OUT/slurmd.out" 2>&1 || skip "slurmd does not start here" "$OUT/slurmd.log"

# The node comes up idle (a slurmd that cannot run jobs here never does).
k=0
until [ "$(sinfo -h -n sumitest -o %T 2>/dev/null)" = idle ]; do
  k=$((k + 1))
  [ $k -gt 60 ] && skip "the node never became idle ($(sinfo -h -o %T 2>&1))" "$OUT/slurmd.log"
  sleep 1
done

# finished JOB...: wait until none of the jobs is pending or running
finished() {
  t=0
  while squeue -h -j "$(echo "$@" | tr ' ' ',')" -o %i 2>/dev/null | grep -q .; do
    t=$((t + 2)); [ $t -gt "$WAIT" ] && return 1
    sleep 2
  done
}
# state JOB: the final state of a job (of every job of an array)
state() { scontrol show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort -u | tr '\n' ' '; }

# A frame as 2x3 tiles through scripts/slurm/tiles.sh, and an animation
# as a frame array (two frames a job), against one process each.
scene=$ROOT/examples/teapot_toon.npr
anim=$ROOT/examples/threshold_zoom.npr
"$SUMI" render "$scene" -o "$OUT/whole.png" || bad "the single render failed"
"$SUMI" render "$anim" --frames 0:5 --quiet -o "$OUT/anim_####.png" || bad "the single animation failed"
cd "$OUT/jobs" || exit 1
ids=$(SUMI="$SUMI" sh "$ROOT/scripts/slurm/tiles.sh" "$scene" 2x3 "$OUT/jobs/frame.png") ||
  bad "tiles.sh could not submit"
frames=$(SUMI="$SUMI" sbatch --parsable --array=0-5:2 "$ROOT/scripts/slurm/frames.sbatch" "$anim" 0:5 \
  "$OUT/jobs/anim_####.png") || bad "frames.sbatch could not be submitted"
if finished $ids $frames; then ok; else bad "the jobs did not finish in $WAIT s"; fi

tiles=${ids% *}; assemble=${ids#* }
[ "$(state "$tiles")" = "COMPLETED " ] && ok || bad "the tile jobs ended $(state "$tiles")"
[ "$(state "$assemble")" = "COMPLETED " ] && ok || bad "the assemble job ended $(state "$assemble")"
[ "$(state "$frames")" = "COMPLETED " ] && ok || bad "the frame jobs ended $(state "$frames")"
if cmp -s "$OUT/whole.png" "$OUT/jobs/frame.png"; then ok
else bad "the assembled frame differs from the single render ($OUT/jobs/frame.png)"; fi
s=1; for f in 0000 0001 0002 0003 0004 0005; do cmp -s "$OUT/anim_$f.png" "$OUT/jobs/anim_$f.png" || s=0; done
if [ "$s" = 1 ]; then ok; else bad "the array's frames differ from the single run's ($OUT/jobs)"; fi
if [ "$failed" != 0 ]; then
  echo "  logs: $OUT/jobs/*.log, $OUT/slurmctld.log, $OUT/slurmd.log"
  for log in "$OUT"/jobs/*.log; do [ -s "$log" ] && { echo "  $(basename "$log"):"; tail -3 "$log" | sed 's/^/    /'; }; done
fi

echo "$passed passed, $failed failed"
[ "$failed" = 0 ]
