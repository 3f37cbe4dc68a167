#!/usr/bin/env bash
# A real Slurm cluster of one node on localhost renders an animated
# sequence through `reyes farm slurm`, and the result is checked against
# the same frames rendered in one local process:
#
#  1. installs Debian's slurm-wlm and munge if missing, makes a munge key
#     and starts munged, slurmctld and slurmd under a private directory
#     (a slurm.conf whose node line is `slurmd -C`'s, the machine's CPUs);
#  2. renders the 12 frames of .ci/slurm-teapot.toml locally, then submits
#     them as a job array of 4 tasks (3 frames each) and waits for it;
#  3. checks that every frame exists and is byte-identical to the local one;
#  4. deletes two frames, runs what `reyes farm status` advises (a new job
#     array of the missing frames) and checks that only those two were
#     rendered again (the other frames' modification times stay).
#
# The daemons are stopped on exit; if anything fails, their logs and the
# tasks' logs are shown. Needs root (the daemons run as root) and a built
# target/release/reyes (built here if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
reyes=$root/target/release/reyes
scene=$root/.ci/slurm-teapot.toml
timeout_s=${REYES_SLURM_TIMEOUT:-600}

if [ ! -x "$reyes" ]; then
    cargo build --release -p reyes
fi
if ! command -v slurmctld >/dev/null 2>&1 || ! command -v munged >/dev/null 2>&1; then
    echo "installing Debian's slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq slurm-wlm munge >/dev/null
fi

work=$(mktemp -d /tmp/reyes-slurm.XXXXXX)
export SLURM_CONF=$work/slurm.conf
ok=0

show_logs() {
    for log in "$work"/munged.log "$work"/slurmctld.log "$work"/slurmd.log "$work"/frames/logs/*.log; do
        [ -f "$log" ] || continue
        echo "===== $log"
        tail -n 60 "$log"
    done
}
stop_daemons() {
    if [ "$ok" != 1 ]; then
        echo "slurm-test: FAILED; the daemons' and tasks' logs follow" >&2
        show_logs >&2
    fi
    scancel --user=root >/dev/null 2>&1 || true
    for pid in "$work"/slurmd.pid "$work"/slurmctld.pid "$work"/munged.pid; do
        if [ -f "$pid" ]; then
            kill "$(cat "$pid")" 2>/dev/null || true
        fi
    done
    sleep 1
    if [ "$ok" = 1 ]; then
        rm -rf "$work"
    fi
}
trap stop_daemons EXIT

fail() {
    echo "slurm-test: $*" >&2
    exit 1
}

# munge: a fresh key, and a daemon with its socket in $work.
mkdir -p "$work/munge"
# Clients reach the socket through this directory.
chmod 755 "$work" "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --key-file="$work/munge/munge.key" --socket="$work/munge/munge.socket" \
    --pid-file="$work/munged.pid" --log-file="$work/munged.log" \
    --seed-file="$work/munge/munge.seed" --force ||
    fail "munged did not start"

# One node: this machine, as slurmd -C describes it.
host=$(hostname -s)
node_line=$(slurmd -C | head -n 1 | sed "s/^NodeName=[^ ]*/NodeName=$host NodeAddr=127.0.0.1/")
mkdir -p "$work/state" "$work/spool"
cat > "$SLURM_CONF" <<CONF
ClusterName=reyes-ci
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MailProg=/bin/true
$node_line State=UNKNOWN
PartitionName=ci Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
slurmctld -i -f "$SLURM_CONF" || fail "slurmctld did not start"
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"

# The node must come up idle.
for _ in $(seq 60); do
    state=$(sinfo -h -N -o '%T' 2>/dev/null | head -n 1 || true)
    [ "$state" = idle ] && break
    sleep 1
done
[ "$state" = idle ] || fail "the node is '$state', not idle, after 60 s"
echo "slurm-test: one-node cluster up: $node_line"

# Waits for job $1 to leave the queue, within the timeout.
wait_for_job() {
    local job=$1 waited=0
    while [ -n "$(squeue -h -j "$job" -o '%i' 2>/dev/null)" ]; do
        [ "$waited" -lt "$timeout_s" ] || fail "job $job still queued or running after $timeout_s s"
        sleep 2
        waited=$((waited + 2))
    done
    echo "slurm-test: job $job done after about $waited s"
}
# The job id in `reyes farm slurm --submit`'s output ($1).
job_of() {
    sed -n 's/^submitted batch job \([0-9]*\).*/\1/p' <<<"$1"
}

frames=$work/frames/teapot.####.png
"$reyes" render "$scene" --frames 1-12 -o "$work/local/teapot.####.png" --quiet >/dev/null

submitted=$("$reyes" farm slurm "$scene" --frames 1-12 --chunk 3 -o "$frames" --submit -- --quiet)
echo "$submitted"
job=$(job_of "$submitted")
[ -n "$job" ] || fail "no job id in: $submitted"
grep -q '^#SBATCH --array=0-3$' "$work/frames/slurm-teapot.sbatch" || fail "not an array of 4 tasks"
wait_for_job "$job"
logs=$(ls "$work/frames/logs/reyes-slurm-teapot-${job}"_*.log | wc -l)
[ "$logs" = 4 ] || fail "$logs task logs, not 4"

for n in $(seq -w 1 12); do
    name=teapot.00$n.png
    [ -f "$work/frames/$name" ] || fail "frame $n is missing"
    cmp "$work/local/$name" "$work/frames/$name" || fail "frame $n differs from the local render"
done
echo "slurm-test: 12 frames from 4 array tasks, identical to one local process"
"$reyes" farm status "$scene" --frames 1-12 -o "$frames" >/dev/null || fail "farm status: frames missing"

# Delete two frames; render again what the status advises.
stamps() {
    for n in $(seq -w 1 12); do stat -c '%n %.9Y' "$work/frames/teapot.00$n.png"; done
}
before=$(stamps)
rm "$work/frames/teapot.0004.png" "$work/frames/teapot.0009.png"
sleep 1
status=$("$reyes" farm status "$scene" --frames 1-12 --chunk 3 -o "$frames" -- --quiet || true)
echo "$status"
advice=$(sed -n '/on Slurm/{n;p}' <<<"$status")
[ -n "$advice" ] || fail "farm status advised no Slurm command"
grep -q -- "--frames '4,9'" <<<"$advice" || fail "the advice is not frames 4 and 9: $advice"
submitted=$(eval "$advice")
echo "$submitted"
job=$(job_of "$submitted")
[ -n "$job" ] || fail "no job id in: $submitted"
wait_for_job "$job"
after=$(stamps)
changed=$({ diff <(echo "$before") <(echo "$after") || true; } | sed -n 's/^> .*teapot\.\(00[0-9]*\)\.png .*/\1/p' | tr '\n' ' ')
[ "$changed" = "0004 0009 " ] || fail "rendered again: '$changed', not frames 4 and 9"
for n in 04 09; do
    cmp "$work/local/teapot.00$n.png" "$work/frames/teapot.00$n.png" || fail "frame $n differs"
done
"$reyes" farm status "$scene" --frames 1-12 -o "$frames" || fail "farm status: frames missing"
echo "slurm-test: frames 4 and 9, and only they, rendered again through the status's advice"
ok=1
