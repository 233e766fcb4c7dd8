#!/usr/bin/env bash
# The farm, live (docs/farm.md): scripts/farm/plan.sh's printed commands run as printed, on real
# daemons started here for the test and stopped at its end, even when it fails.
#   slurm: a single-node Slurm cluster (munged, slurmctld, slurmd on loopback, in a temporary
#          folder). The plan's `sbatch ... && sbatch --dependency=afterok:...` line renders the
#          parts as an array job and merges them: the image is the single run's, byte for byte.
#          A held task shows in `merge --status` as the part not there yet; a cancelled task
#          leaves a status that names it and a merge that refuses, until it is rendered again.
#   ssh:   GNU parallel over --sshlogin to this machine through a real sshd (its own port, host
#          key and a test key): the parts are rendered over ssh, and the merge is the single run.
# Exit status 77 (ctest's SKIP_RETURN_CODE) when it cannot run here: not root, the Debian
# packages cannot be installed, or a port is taken.
#
#   tests/farm/live.sh BUILD_DIR slurm|ssh
set -euo pipefail
BUILD=$(cd "$1" && pwd)
MODE=$2
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BIN=$BUILD/bin
cd "$ROOT"

SKIPPED=77
skip() { echo "SKIPPED: $*"; exit $SKIPPED; }
fail() { echo "FAIL: $*" >&2; exit 1; }
same() {  # same FILE_A FILE_B WHAT: byte for byte
    cmp -s "$1" "$2" || fail "$3: $1 and $2 differ"
}
# wait_for SECONDS WHAT COMMAND...: polls COMMAND every 0.2 s until it succeeds.
wait_for() {
    local seconds=$1 what=$2
    shift 2
    local deadline=$((SECONDS + seconds))
    until "$@"; do
        [ $SECONDS -lt $deadline ] || fail "$what: not within $seconds s"
        sleep 0.2
    done
}
port_free() {  # port_free PORT: nothing listens on it (on any address; as the daemons bind)
    python3 -c 'import socket, sys
s = socket.socket()
s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
s.bind(("0.0.0.0", int(sys.argv[1])))' "$1" 2> /dev/null
}

[ "$(id -u)" -eq 0 ] || skip "the $MODE farm test starts daemons as root: run it as root"
case $MODE in
    slurm) PACKAGES=(slurm-wlm munge) ;;
    ssh) PACKAGES=(openssh-server openssh-client parallel) ;;
    *) fail "unknown mode $MODE" ;;
esac
# scripts/test.sh installs them; a test run on its own installs what is missing.
(source scripts/setup.sh > /dev/null && install_missing_packages "${PACKAGES[@]}") ||
    skip "could not install ${PACKAGES[*]}"

# The daemons this test starts, by pid; each is stopped at exit, whatever the exit.
WORK=$(mktemp -d /tmp/lessons_farm_live.XXXXXX)
chmod 755 "$WORK"
DAEMONS=()
CLEANUP=()  # commands run before the daemons are stopped (cancel the jobs)
stop_all() {
    local status=$?
    set +e
    for c in "${CLEANUP[@]}"; do eval "$c"; done
    local i
    for ((i = ${#DAEMONS[@]} - 1; i >= 0; --i)); do  # the last started first
        local pid=${DAEMONS[i]}
        kill -TERM "$pid" 2> /dev/null || continue
        for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.2; done
        kill -KILL "$pid" 2> /dev/null
        wait "$pid" 2> /dev/null
    done
    if [ "$status" -ne 0 ] && [ "$status" -ne $SKIPPED ]; then
        echo "--- the logs in $WORK:" >&2
        tail -n 20 "$WORK"/*.log >&2 2> /dev/null
    fi
    rm -rf "$WORK"
    exit "$status"
}
trap stop_all EXIT
trap 'exit 143' TERM INT

L=04_rendering_equation
FLAGS=(--scene scenes/cornell_spheres.toml --width 64 --height 48)
SPP=16
"$BIN/$L" --quiet "${FLAGS[@]}" --spp $SPP --out "$WORK/single"

# slurm_plan DIR: plan.sh --slurm into DIR, then the printed sbatch line, run as printed while
# the partition is down, so that the test can hold or cancel a task before any runs. Sets
# JOBID (the array job's) and MERGE_JOBID.
slurm_plan() {
    local dir=$1
    scripts/farm/plan.sh --lesson $L --spp $SPP --parts 4 --dir "$dir" --slurm --bin "$BIN" \
        -- "${FLAGS[@]}" > "$dir.plan.txt"
    cat "$dir.plan.txt"
    local line
    line=$(grep '^jobid=$(sbatch ' "$dir.plan.txt") || fail "the plan prints no sbatch line"
    [[ $line == *" && sbatch --dependency=afterok:"* ]] ||
        fail "the sbatch line has no dependent merge job"
    scontrol update PartitionName=farm State=DOWN
    bash -c "$line" > "$dir.submitted.txt"
    cat "$dir.submitted.txt"
    JOBID=$(sed -n 's/^Submitted array job \([0-9]*\)$/\1/p' "$dir.submitted.txt")
    MERGE_JOBID=$(sed -n 's/^Submitted batch job \([0-9]*\)$/\1/p' "$dir.submitted.txt")
    [ -n "$JOBID" ] && [ -n "$MERGE_JOBID" ] || fail "the sbatch line did not submit two jobs"
}
job_state() {  # job_state ID: its state (PENDING, RUNNING, COMPLETED, CANCELLED, ...)
    scontrol show job "$1" 2> /dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -1
}
ACTIVE=PENDING,RUNNING,CONFIGURING,COMPLETING
ONE_NOT_THERE="incomplete: 1 of the 4 parts named is not there or unreadable"
active() { squeue -h -r -t $ACTIVE -o %i "$@" 2> /dev/null | sort; }  # jobs or tasks, one a line
only_task_active() { [ "$(active -j "$JOBID")" = "$1" ]; }
array_done() { [ -z "$(active -j "$JOBID")" ]; }
never_satisfied() {
    scontrol show job "$1" | grep -q 'JobState=PENDING Reason=DependencyNeverSatisfied'
}
job_done() {  # ended, in any way
    case $(job_state "$1") in PENDING | RUNNING | CONFIGURING | COMPLETING | "") return 1 ;; esac
}
node_idle() {  # (and the daemons still there: a bad configuration stops them at once)
    local pid
    for pid in "${DAEMONS[@]}"; do kill -0 "$pid" 2> /dev/null || fail "a daemon exited (pid $pid)"; done
    [ "$(sinfo -h -o %T 2> /dev/null)" = idle ]
}
cancel_all_jobs() {  # every job of this cluster, waiting (bounded) for their steps to end
    timeout 15 scancel --user=root 2> /dev/null
    local deadline=$((SECONDS + 15))
    while [ $SECONDS -lt $deadline ] && [ -n "$(timeout 5 squeue -h -t $ACTIVE 2> /dev/null)" ]; do
        sleep 0.2
    done
}

run_slurm() {
    for p in 16817 16818; do port_free $p || skip "port $p (slurmctld, slurmd) is taken"; done
    # munge: a key of the test's own, and its own socket.
    dd if=/dev/urandom of="$WORK/munge.key" bs=1024 count=1 status=none
    chmod 400 "$WORK/munge.key"
    munged --foreground --key-file="$WORK/munge.key" --socket="$WORK/munge.socket" \
        --pid-file="$WORK/munged.pid" --seed-file="$WORK/munged.seed" > "$WORK/munged.log" 2>&1 &
    DAEMONS+=($!)
    wait_for 10 "munged starts" test -S "$WORK/munge.socket"

    # One node, this machine as slurmd -C sees it, named farmnode (a name that needs no resolving)
    # and reached on loopback only; the daemons run as root.
    local host node
    host=$(hostname -s)  # (slurmctld runs where SlurmctldHost names)
    node=$(slurmd -C | head -1 | sed 's/^NodeName=[^ ]*/NodeName=farmnode/')
    mkdir -p "$WORK/slurmctld" "$WORK/slurmd"
    cat > "$WORK/slurm.conf" << CONF
ClusterName=lessonsfarm
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
CommunicationParameters=NoInAddrAny,NoCtldInAddrAny
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$WORK/munge.socket
StateSaveLocation=$WORK/slurmctld
SlurmdSpoolDir=$WORK/slurmd
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/slurmctld.log
SlurmdLogFile=$WORK/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=farm Nodes=farmnode Default=YES MaxTime=INFINITE State=UP
CONF
    export SLURM_CONF=$WORK/slurm.conf
    slurmctld -D -f "$SLURM_CONF" > "$WORK/slurmctld.stderr.log" 2>&1 &
    DAEMONS+=($!)
    slurmd -D -N farmnode -f "$SLURM_CONF" > "$WORK/slurmd.stderr.log" 2>&1 &
    DAEMONS+=($!)
    # Before the daemons stop: every job of this cluster cancelled, and its steps gone.
    CLEANUP+=(cancel_all_jobs)
    wait_for 30 "the node idle in sinfo" node_idle
    sinfo

    # 1. Task 3 held: the others render, merge --status shows them and part 3 not there yet;
    # released, it renders, and the dependent merge job gives the single run, byte for byte.
    local dir=$WORK/run
    slurm_plan "$dir"
    scontrol hold "${JOBID}_3"
    scontrol update PartitionName=farm State=UP
    wait_for 120 "tasks 0-2 of array job $JOBID done" only_task_active "${JOBID}_3"
    "$BIN/merge" --status $(cat "$dir/part_files.txt") > "$WORK/status.txt"
    cat "$WORK/status.txt"
    grep -qx "3 of 4 parts there" "$WORK/status.txt" || fail "merge --status while task 3 is held"
    for k in 0 1 2; do
        grep -qF "$dir/part_000$k.exr: pixels 0:64,0:48, samples $((k * 4)):$((k * 4 + 4))," \
            "$WORK/status.txt" || fail "merge --status does not list part $k"
    done
    grep -qF "$dir/part_0003.exr: not there yet" "$WORK/status.txt" ||
        fail "merge --status does not name part 3 as not there yet"
    tail -1 "$WORK/status.txt" | grep -qx "$ONE_NOT_THERE" ||
        fail "merge --status does not say the farm is incomplete"
    [ "$(job_state "$MERGE_JOBID")" = PENDING ] || fail "the merge job ran before task 3"
    scontrol release "${JOBID}_3"
    wait_for 120 "the merge job $MERGE_JOBID done" job_done "$MERGE_JOBID"
    [ "$(job_state "$MERGE_JOBID")" = COMPLETED ] ||
        { cat "$dir"/slurm_merge.log; fail "the merge job ended $(job_state "$MERGE_JOBID")"; }
    same "$WORK/single.exr" "$dir/merged.exr" "Slurm array job of 4 parts and its merge job"
    echo "ok: Slurm: the printed sbatch line ran 4 array tasks and the merge job;" \
        "merged = single run, byte for byte"

    # 2. Task 1 cancelled: the array fails, the merge job waits for ever (its dependency can never
    # be met: Slurm's default, without DependencyParameters=kill_invalid_depend), merge --status
    # names part 1, and the merge refuses.
    dir=$WORK/cancelled
    slurm_plan "$dir"
    scancel "${JOBID}_1"
    scontrol update PartitionName=farm State=UP
    wait_for 120 "array job $JOBID done" array_done
    wait_for 30 "the merge job $MERGE_JOBID left waiting" never_satisfied "$MERGE_JOBID"
    "$BIN/merge" --status $(cat "$dir/part_files.txt") > "$WORK/status.txt"
    cat "$WORK/status.txt"
    grep -qF "$dir/part_0001.exr: not there yet" "$WORK/status.txt" ||
        fail "merge --status does not name the cancelled part 1"
    grep -qF "missing: samples 4:8 of pixels 0:64,0:48" "$WORK/status.txt" ||
        fail "merge --status does not name the missing samples 4:8"
    tail -1 "$WORK/status.txt" | grep -qx "$ONE_NOT_THERE" ||
        fail "merge --status does not say the farm is incomplete"
    local status=0
    "$BIN/merge" --quiet $(cat "$dir/part_files.txt") --out "$dir/merged" 2> "$WORK/err.txt" || status=$?
    cat "$WORK/err.txt"
    [ "$status" -ne 0 ] || fail "the merge of a farm with a cancelled task did not refuse"
    grep -qF "$dir/part_0001.exr" "$WORK/err.txt" || fail "the refused merge does not name part 1"
    [ ! -e "$dir/merged.exr" ] || fail "the refused merge wrote an image"
    echo "ok: Slurm: task ${JOBID}_1 cancelled: the merge job waits (DependencyNeverSatisfied)," \
        "merge --status names part 1, merge refuses (exit $status)"

    # 3. The way back (docs/farm.md): the waiting merge job cancelled, part 1 rendered again as
    # task 1 of the same script, and the plan's merge line gives the single run.
    scancel "$MERGE_JOBID"
    local again
    again=$(sbatch --parsable --array=1 "$dir/farm.sbatch")
    wait_for 120 "task 1 again (job $again) done" job_done "${again}_1"
    [ "$(job_state "${again}_1")" = COMPLETED ] || fail "task 1 again ended $(job_state "${again}_1")"
    bash -c "$(grep '/merge ' "$dir.plan.txt" | grep -v -e --status -e '^srun' | head -1)"
    same "$WORK/single.exr" "$dir/merged.exr" "Slurm: part 1 rendered again, then merged"
    echo "ok: Slurm: part 1 rendered again with sbatch --array=1, merged = single run, byte for byte"
}

run_ssh() {
    local port=16822
    port_free $port || skip "port $port (sshd) is taken"
    # sshd with its own host key, letting in root with a test key only, on loopback.
    ssh-keygen -q -t ed25519 -N '' -C lessons-farm-host -f "$WORK/host_key"
    ssh-keygen -q -t ed25519 -N '' -C lessons-farm-user -f "$WORK/user_key"
    cp "$WORK/user_key.pub" "$WORK/authorized_keys"
    cat > "$WORK/sshd_config" << CONF
Port $port
ListenAddress 127.0.0.1
HostKey $WORK/host_key
PidFile $WORK/sshd.pid
AuthorizedKeysFile $WORK/authorized_keys
StrictModes no
PermitRootLogin prohibit-password
PasswordAuthentication no
KbdInteractiveAuthentication no
UsePAM no
LogLevel VERBOSE
CONF
    # The client: that host key, known in advance; that key; nothing asked.
    echo "[127.0.0.1]:$port $(cut -d' ' -f1,2 "$WORK/host_key.pub")" > "$WORK/known_hosts"
    cat > "$WORK/ssh_config" << CONF
Host farmhost
    HostName 127.0.0.1
    Port $port
    User root
    IdentityFile $WORK/user_key
    IdentitiesOnly yes
    UserKnownHostsFile $WORK/known_hosts
    StrictHostKeyChecking yes
    BatchMode yes
CONF
    if [ ! -d /run/sshd ]; then  # sshd's privilege separation folder (its service makes it)
        mkdir -m 755 /run/sshd
        CLEANUP+=('rmdir /run/sshd')
    fi
    /usr/sbin/sshd -D -e -f "$WORK/sshd_config" > "$WORK/sshd.log" 2>&1 &
    DAEMONS+=($!)
    export PARALLEL_SSH="ssh -F $WORK/ssh_config"  # how GNU parallel logs in
    wait_for 20 "sshd accepts the test key" $PARALLEL_SSH farmhost true

    local dir=$WORK/farm
    mkdir -p "$dir"
    scripts/farm/plan.sh --lesson $L --spp $SPP --parts 4 --tiles 1x2 --hosts farmhost \
        --dir "$dir" --bin "$BIN" -- "${FLAGS[@]}" > "$WORK/plan.txt"
    cat "$WORK/plan.txt"
    local line logins
    line=$(grep '^parallel .*--sshlogin farmhost ' "$WORK/plan.txt") ||
        fail "the plan prints no GNU parallel line over ssh"
    logins=$(grep -c 'Accepted publickey for root' "$WORK/sshd.log")
    bash -c "$line"
    logins=$(($(grep -c 'Accepted publickey for root' "$WORK/sshd.log") - logins))
    [ "$logins" -ge 8 ] ||
        fail "GNU parallel logged in $logins times through sshd, not once per part (8)"
    "$BIN/merge" --status $(cat "$dir/part_files.txt") | tail -1 | grep -qx "complete: merge them" ||
        fail "merge --status does not see the farm complete"
    bash -c "$(grep '/merge ' "$WORK/plan.txt" | grep -v -- --status | head -1)"
    same "$WORK/single.exr" "$dir/merged.exr" "GNU parallel over ssh, 8 parts"
    echo "ok: GNU parallel over ssh (sshd on 127.0.0.1:$port, $logins logins): 8 parts merged" \
        "= single run, byte for byte"
}

run_$MODE
