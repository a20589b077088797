#!/usr/bin/env bash
# The Slurm profile (experiments/profiles/slurm) against a real Slurm: a single-node cluster
# started on this machine for the test (munged with its own key and socket, slurmctld and slurmd
# with a slurm.conf of the test: proctrack/linuxproc, task/none, no accounting, a job completion
# log, free ports, state and logs in a temporary folder), then
#   snakemake -s experiments/Snakefile --profile experiments/profiles/slurm --config ...
# on a four-point sweep (points that differ: each reaches contact). Checks: every point and the
# merge ran as a Slurm job that completed (the job ids Snakemake got from sbatch, each in Slurm's
# job completion log, each with its slurm-<id>.log, which shows the point it ran); the profile's
# status command reports a held job running and a cancelled one failed; runs.csv equals the same
# sweep run by `harness sweep` alone, except the timing columns (t_*_us: wall-clock medians,
# never equal between two runs). A trap stops Snakemake (its process group), cancels the jobs
# left, stops the daemons by their pid files (TERM, then KILL) whatever happens, and removes the
# folder.
# Runs as any user: the daemons run as the user running the test (SlurmUser, SlurmdUser), and so
# do the jobs. Needs Debian's slurmctld, slurmd, slurm-client and munge (scripts/install-deps.sh
# installs them): skipped (77) only when not root and they are missing; as root, missing
# packages fail the test. The folder is made by mktemp -d (TMPDIR), which must allow executables
# (slurmd runs the job scripts from its spool folder there) and be sticky if world-writable
# (munged refuses its socket and log otherwise).
# Usage: test_slurm.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
PY=${PYTHON:-/usr/bin/python3}
SNAKEMAKE=$(command -v snakemake || echo /usr/bin/snakemake)
PATH="$PATH:/usr/sbin:/sbin"
missing=()
for c in munged munge slurmctld slurmd sbatch squeue scontrol sinfo scancel; do
  command -v "$c" >/dev/null || missing+=("$c")
done
[[ -x "$SNAKEMAKE" ]] || missing+=(snakemake)
if [[ ${#missing[@]} -gt 0 ]]; then
  if [[ $(id -u) -ne 0 ]]; then
    echo "SKIP: not root and missing ${missing[*]} (scripts/install-deps.sh installs them)"; exit 77
  fi
  echo "0 passed, 1 failed"
  echo "FAIL: missing ${missing[*]} (scripts/install-deps.sh installs slurmctld slurmd slurm-client munge snakemake)"
  exit 1
fi

T=$(mktemp -d)
# munged requires every folder above its socket to be searchable by all.
chmod 755 "$T"
DAEMONS=(slurmd slurmctld munged)   # stop order: the node, the controller, then authentication
export SLURM_CONF="$T/slurm.conf"
# Nothing of the caller's Slurm or Snakemake settings (sbatch reads SBATCH_*).
for v in $(compgen -e | grep -E '^(SBATCH_|SLURM_JOB|SNAKEMAKE_PROFILE$)'); do unset "$v"; done

alive() {  # a process that exists and is not a zombie (one that ended, not yet reaped)
  local st
  st=$(sed 's/^.*) //' "/proc/$1/stat" 2>/dev/null) || return 1
  [[ -n "$st" && "${st:0:1}" != Z ]]
}
# Stops a daemon by its pid file: TERM, up to 5 s for it to end, then KILL. The pid is used only
# while /proc says it is still that daemon (the daemons remove their pid file when they end).
stop_daemon() {
  local f="$T/$1.pid" pid i
  [[ -s "$f" ]] || return 0
  pid=$(<"$f")
  [[ "$pid" =~ ^[0-9]+$ ]] || return 0
  grep -qx "$1" "/proc/$pid/comm" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null
  for i in $(seq 50); do alive "$pid" || return 0; sleep 0.1; done
  echo "stopping $1 (pid $pid): still running 5 s after TERM: KILL"
  kill -KILL "$pid" 2>/dev/null
}
show_logs() {
  local f
  for f in munged.log slurmctld.log slurmd.log snakemake.log; do
    [[ -f "$T/$f" ]] && { echo "--- $f (last 25 lines)"; tail -25 "$T/$f"; }
  done
}
SNAKE_PID=
cleanup() {
  local i
  # Snakemake first (on SIGTERM it would wait for its running jobs): its group, TERM then KILL.
  if [[ -n "$SNAKE_PID" ]] && alive "$SNAKE_PID"; then
    kill -TERM -- "-$SNAKE_PID" 2>/dev/null
    for i in $(seq 20); do alive "$SNAKE_PID" || break; sleep 0.1; done
    kill -KILL -- "-$SNAKE_PID" 2>/dev/null
  fi
  # Jobs still queued or running (a failure half-way) go first, while the controller is up:
  # slurmstepd and the job's processes outlive slurmd.
  if [[ -s "$T/slurmctld.pid" ]] && scontrol ping >/dev/null 2>&1; then
    scancel --full --user="$(id -un)" >/dev/null 2>&1
    for i in $(seq 50); do [[ -z "$(squeue -h -o %i 2>/dev/null)" ]] && break; sleep 0.1; done
  fi
  for d in "${DAEMONS[@]}"; do stop_daemon "$d"; done
  rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
pass=0; fail=0
die() { fail=$((fail+1)); echo "FAIL: $*"; show_logs; echo "$pass passed, $fail failed"; exit 1; }
wait_for() {  # wait_for SECONDS COMMAND...: until COMMAND succeeds, polled every 0.2 s
  local n=$(( $1 * 5 )); shift
  while (( n-- > 0 )); do "$@" >/dev/null 2>&1 && return 0; sleep 0.2; done
  return 1
}

# --- munge: its own key (0400, owned by the user munged runs as), socket, pid file and log.
mungekey -c -b 1024 -k "$T/munge.key" >/dev/null 2>&1 ||
  dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 status=none
chmod 0400 "$T/munge.key"
munged --key-file="$T/munge.key" --socket="$T/munge.socket" --pid-file="$T/munged.pid" \
  --log-file="$T/munged.log" --seed-file="$T/munged.seed" > "$T/munged.out" 2>&1 ||
  die "munged did not start: $(cat "$T/munged.out")"
wait_for 10 munge -S "$T/munge.socket" -n || die "munged answers no credential request on its socket"

# --- slurm.conf: this node as slurmd -C sees it (CPUs, sockets, cores, memory), reached at
# 127.0.0.1 (no name resolution needed), two free ports.
read -r CTLD_PORT SLURMD_PORT < <("$PY" -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])') || die "no free ports"
NODE=$(hostname -s)
HW=$(slurmd -C 2>/dev/null | grep -m1 '^NodeName=' | sed 's/^NodeName=[^ ]* //')
[[ "$HW" == *CPUs=* && "$HW" == *RealMemory=* ]] || die "slurmd -C reports no CPUs and memory: $(slurmd -C 2>&1)"
ME=$(id -un)
mkdir -p "$T/state" "$T/spool" "$T/work"
cat > "$SLURM_CONF" <<EOF
ClusterName=harnesstest
SlurmctldHost=$NODE(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=$ME
SlurmdUser=$ME
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge.socket
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$T/jobcomp.txt
MpiDefault=none
MailProg=/bin/true
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
NodeName=$NODE NodeAddr=127.0.0.1 $HW State=UNKNOWN
PartitionName=harness Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -f "$SLURM_CONF" > "$T/slurmctld.out" 2>&1 || die "slurmctld did not start: $(cat "$T/slurmctld.out")"
wait_for 20 scontrol ping || die "slurmctld does not answer scontrol ping"
slurmd -f "$SLURM_CONF" -N "$NODE" > "$T/slurmd.out" 2>&1 || die "slurmd did not start: $(cat "$T/slurmd.out")"
node_idle() { [[ "$(sinfo -h -n "$NODE" -o %t)" == idle ]]; }
wait_for 30 node_idle || die "node $NODE not idle: $(sinfo -h -N -o '%N %t %E' 2>&1)"
pass=$((pass+1))   # the cluster is up

# --- The sweep through the committed profile; only the working folder is the test's.
cp "$SRC/experiments/scenes/sphere_collision.json" "$T/scene.json"
GRID=(contacts.0.eliminator=line,plane contacts.0.force=0.01,auto)
# Short (under a second a point) but past first contact: coarser spheres, the voxel model, 1800
# steps exactly (the gap closes at about step 1600), no references, no frames.
SETS=(time.steps=1800 time.settle=null contacts.0.detector=voxel bodies.0.shape.subdivisions=2
      bodies.1.shape.subdivisions=2 'references.solvers=[]' output.frames_every=0)
POINTS=4
grid_json=$("$PY" -c 'import json,sys; print(json.dumps(sys.argv[1:]))' "${GRID[@]}")
set_json=$("$PY" -c 'import json,sys; print(json.dumps(sys.argv[1:]))' "${SETS[@]}")
start=$SECONDS
# In the background, so that a signal to the test runs its trap at once (bash runs traps only
# between foreground commands), and in a process group of its own, which the trap kills first.
(cd "$T/work" && exec setsid timeout 300 "$SNAKEMAKE" -s "$SRC/experiments/Snakefile" \
   --profile "$SRC/experiments/profiles/slurm" --directory "$T/work" \
   --config scene="$T/scene.json" "harness=$H" "out=$T/sweep" "grid=$grid_json" "set=$set_json") \
  > "$T/snakemake.log" 2>&1 &
SNAKE_PID=$!
wait "$SNAKE_PID"; rc=$?
SNAKE_PID=
echo "snakemake --profile experiments/profiles/slurm: exit $rc after $((SECONDS - start)) s"
[[ $rc -eq 0 ]] && pass=$((pass+1)) || die "snakemake exit $rc"

# Every job Snakemake submitted is a Slurm job id (sbatch --parsable); one per point + the merge.
mapfile -t JOBS < <(sed -n "s/^Submitted job [0-9]* with external jobid '\([0-9]*\)'.*/\1/p" "$T/snakemake.log")
[[ ${#JOBS[@]} -eq $((POINTS + 1)) ]] && pass=$((pass+1)) ||
  { fail=$((fail+1)); echo "FAIL: ${#JOBS[@]} Slurm jobs submitted (${JOBS[*]}), expected $((POINTS + 1))"; }
# Slurm records a job in its completion log when the job has ended: wait for the queue to empty.
queue_empty() { [[ -z "$(squeue -h -o %i)" ]]; }
wait_for 30 queue_empty || { fail=$((fail+1)); echo "FAIL: jobs still queued: $(squeue 2>&1)"; }
points=0; merges=0
for j in "${JOBS[@]}"; do
  rec=$(grep -m1 "^JobId=$j " "$T/jobcomp.txt" 2>/dev/null)
  state=$(sed -n 's/.* JobState=\([A-Z_]*\) .*/\1/p' <<<"$rec")
  name=$(sed -n 's/.* Name=\([^ ]*\) .*/\1/p' <<<"$rec")
  if [[ "$state" == COMPLETED && -f "$T/work/slurm-$j.log" ]]; then
    [[ "$name" == harness-point ]] && points=$((points+1))
    [[ "$name" == harness-merge ]] && merges=$((merges+1))
  else
    fail=$((fail+1)); echo "FAIL: Slurm job $j: state '${state:-not in the completion log}', name '$name', slurm-$j.log $([[ -f "$T/work/slurm-$j.log" ]] && echo present || echo missing)"
  fi
done
[[ $points -eq $POINTS && $merges -eq 1 ]] && pass=$((pass+1)) ||
  { fail=$((fail+1)); echo "FAIL: completed Slurm jobs: $points points (expected $POINTS), $merges merges (expected 1)"; }
echo "Slurm jobs: ${JOBS[*]} (completed: $points points, $merges merge)"
# Each point ran in its own job: the job's Slurm log holds Snakemake's run of `--index I`.
ran=$(for j in "${JOBS[@]}"; do grep -m1 -o ' --index [0-9]* ' "$T/work/slurm-$j.log" 2>/dev/null; done | awk '{print $2}' | sort -n | tr '\n' ' ')
[[ "$ran" == "$(seq -s ' ' 0 $((POINTS - 1))) " ]] && pass=$((pass+1)) ||
  { fail=$((fail+1)); echo "FAIL: points run in Slurm jobs: '$ran', expected 0 to $((POINTS - 1)) once each"; }
# Each point's log was written by its job (the end-of-run line).
for ((i = 0; i < POINTS; i++)); do
  grep -q "^harness: .*steps" "$T/sweep/logs/point_$i.log" 2>/dev/null && pass=$((pass+1)) ||
    { fail=$((fail+1)); echo "FAIL: no end-of-run line in logs/point_$i.log"; }
done

# The profile's status command (status.py) on a job Slurm holds, then cancels: running, failed.
STATUS="$SRC/experiments/profiles/slurm/status.py"
held=$(sbatch --parsable --hold --job-name=harness-held --output=/dev/null --wrap true 2>&1)
s1=$("$STATUS" "$held" 2>&1); scancel "$held" 2>/dev/null
cancelled() { [[ "$("$STATUS" "$held" 2>&1)" == failed ]]; }
wait_for 10 cancelled; s2=$("$STATUS" "$held" 2>&1)
[[ "$s1" == running && "$s2" == failed ]] && pass=$((pass+1)) ||
  { fail=$((fail+1)); echo "FAIL: status.py on job '$held': '$s1' held (expected running), '$s2' cancelled (expected failed)"; }

# --- The same sweep locally: runs.csv equal but for the timing columns.
gargs=(); for g in "${GRID[@]}"; do gargs+=(--grid "$g"); done
sargs=(); for s in "${SETS[@]}"; do sargs+=(--set "$s"); done
"$H" sweep "$T/scene.json" "${gargs[@]}" "${sargs[@]}" --out "$T/local" -j 2 > "$T/local.log" 2>&1 ||
  { fail=$((fail+1)); echo "FAIL: harness sweep (local) failed"; tail -5 "$T/local.log"; }
if cmp=$("$PY" - "$T/sweep/runs.csv" "$T/local/runs.csv" "$POINTS" 2>&1 <<'EOF'
import csv, re, sys
a, b = ([r for r in csv.DictReader(open(p))] for p in sys.argv[1:3])
n = int(sys.argv[3])
timing = re.compile(r"^t_.*_us$")
if len(a) != n or len(b) != n:
    sys.exit("rows: %d on Slurm, %d local, expected %d" % (len(a), len(b), n))
if list(a[0]) != list(b[0]):
    sys.exit("columns differ: %s vs %s" % (list(a[0]), list(b[0])))
cols = [c for c in a[0] if not timing.match(c)]
bad = ["point %s %s: %r vs %r" % (x["point"], c, x[c], y[c]) for x, y in zip(a, b) for c in cols if x[c] != y[c]]
if bad:
    sys.exit("\n".join(bad[:10]))
if any(x["status"] != "ok" for x in a):
    sys.exit("a point's status is not ok")
print("%d rows x %d columns equal (%d timing columns left out)" % (n, len(cols), len(a[0]) - len(cols)))
EOF
); then pass=$((pass+1)); echo "runs.csv: $cmp"; else fail=$((fail+1)); echo "FAIL: runs.csv differs from the local sweep: $cmp"; fi

[[ $fail -eq 0 ]] || show_logs
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
