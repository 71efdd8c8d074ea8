#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for glint's cluster tests
# (tests/cluster.rs) and for trying `glint job slurm` by hand: munged,
# slurmctld and slurmd as plain processes on loopback, run as root, with
# their own config, munge key, state and logs in one folder. Nothing is
# written to /etc, no systemd unit is used, nothing is ever purged.
#
#   scripts/slurm-local.sh start         # installs Debian's packages when missing
#   source "${GLINT_SLURM_DIR:-${TMPDIR:-/tmp}/glint-slurm}/env"    # SLURM_CONF
#   sbatch --array=0-3 --wait job.sh     # exit code: the highest of any task
#   scripts/slurm-local.sh status        # exit 0 running, 1 partly, 3 stopped
#   scripts/slurm-local.sh stop [--keep] # cancels the jobs, stops the daemons
#                                        # start recorded, removes the folder
#
# Settings (environment):
#   GLINT_SLURM_DIR          the folder     [${TMPDIR:-/tmp}/glint-slurm]
#                            (keep it short: the munge socket's path must fit in 108 bytes)
#   GLINT_SLURM_CTLD_PORT    slurmctld port [6817]
#   GLINT_SLURM_SLURMD_PORT  slurmd port    [6818]
#   GLINT_SLURM_TASK_PLUGIN  task/affinity binds each task to its CPUs, so
#                            glint's default thread count follows them;
#                            task/none where sched_setaffinity is refused [task/affinity]
#   GLINT_SLURM_TIMEOUT      seconds to wait for each daemon [30]
set -euo pipefail

DIR=${GLINT_SLURM_DIR:-${TMPDIR:-/tmp}/glint-slurm}
[[ $DIR = /* ]] || DIR=$PWD/$DIR # slurm.conf wants absolute paths
CTLD_PORT=${GLINT_SLURM_CTLD_PORT:-6817}
SLURMD_PORT=${GLINT_SLURM_SLURMD_PORT:-6818}
TASK_PLUGIN=${GLINT_SLURM_TASK_PLUGIN:-task/affinity}
TIMEOUT=${GLINT_SLURM_TIMEOUT:-30}
CONF=$DIR/etc/slurm.conf
SOCK=$DIR/munge/run/munge.socket
KEY=$DIR/munge/key/munge.key
PIDS=$DIR/pids
MARK=$DIR/.glint-slurm-local # marks the folder as this script's: only such a folder is removed
DAEMONS=(munged slurmctld slurmd) # in the order they start; stopped in reverse
export PATH="$PATH:/usr/sbin:/sbin"
export SLURM_CONF=$CONF

say() { printf 'slurm-local: %s\n' "$*" >&2; }
die() {
    say "error: $*"
    exit 1
}
usage() {
    say "usage: $0 start | stop [--keep] | status"
    exit 2
}

# stat_word PID N: word N of /proc/PID/stat after the command name (1: state, 4: session).
stat_word() {
    local n=$2 stat
    read -r stat 2>/dev/null <"/proc/$1/stat" || return 1
    stat=${stat##*) }
    # shellcheck disable=SC2086 # split into the fields
    set -- $stat
    echo "${!n}"
}

# start_time PID: the process's start time in clock ticks (field 22 of
# /proc/PID/stat); fails for a zombie, which has stopped (PID 1 reaps late).
start_time() {
    local state
    state=$(stat_word "$1" 1) && [ "$state" != Z ] && stat_word "$1" 20
}

# pid_of NAME: prints the PID recorded for daemon NAME when that process
# still runs and is still ours: same start time, argv[0] NAME, and a command
# line naming this folder (PIDs are reused within minutes here).
pid_of() {
    local pid recorded now argv0 cmdline
    [ -s "$PIDS/$1.pid" ] || return 1
    read -r pid recorded <"$PIDS/$1.pid" || return 1
    now=$(start_time "$pid") || return 1
    [ "$now" = "$recorded" ] || return 1
    cmdline=$(tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null) || return 1
    argv0=${cmdline%% *}
    [ "${argv0##*/}" = "$1" ] || return 1
    case $cmdline in *" $DIR/"* | *"=$DIR/"*) ;; *) return 1 ;; esac
    echo "$pid"
}

# launch NAME ARGS...: starts daemon NAME in its foreground mode, in a
# session of its own, and records its PID and start time. (setsid does not
# fork here: a script's background job is no process-group leader, so $! is
# the daemon itself; pid_of checks its argv[0] anyway.)
launch() {
    local name=$1 pid i
    shift
    setsid "$name" "$@" </dev/null >>"$DIR/log/$name.out" 2>&1 &
    pid=$!
    for ((i = 0; i < 50; i++)); do # the exec may not have happened yet
        if [ "$(tr '\0' '\n' <"/proc/$pid/cmdline" 2>/dev/null | head -1)" = "$name" ]; then
            echo "$pid $(start_time "$pid")" >"$PIDS/$name.pid"
            return 0
        fi
        sleep 0.02
    done
    die "$name did not start (see $DIR/log/$name.out)"
}

# wait_for WHAT CMD...: retries CMD every 0.1 s for $TIMEOUT s.
wait_for() {
    local what=$1 i
    shift
    for ((i = 0; i < TIMEOUT * 10; i++)); do
        "$@" >/dev/null 2>&1 && return 0
        sleep 0.1
    done
    die "$what not ready after ${TIMEOUT}s (GLINT_SLURM_TIMEOUT; logs in $DIR/log)"
}

port_free() {
    ! command -v ss >/dev/null 2>&1 || [ -z "$(ss -Hltn "sport = :$1" 2>/dev/null)" ] ||
        die "port $1 is taken by a process this script did not start (set $2)"
}

munge_ok() { munge -n -S "$SOCK" | unmunge -S "$SOCK"; }
node_idle() { [ "$(sinfo -h -n localhost -o %T 2>/dev/null)" = idle ]; }

# cancel_jobs: cancels every job of this cluster while its controller answers,
# so that no job step outlives slurmd.
cancel_jobs() {
    local jobs i
    pid_of slurmctld >/dev/null && scontrol ping >/dev/null 2>&1 || return 0
    jobs=$(squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ')
    [ -n "${jobs// /}" ] || return 0
    say "cancelling jobs $jobs"
    # shellcheck disable=SC2086 # one argument a job
    scancel $jobs 2>/dev/null || true
    for ((i = 0; i < 150; i++)); do
        [ -z "$(squeue -h -o %A 2>/dev/null)" ] && return 0
        sleep 0.1
    done
    say "warning: jobs still listed: $(squeue -h -o %A 2>/dev/null | tr '\n' ' ')"
}

# stop_daemons: TERM to each recorded daemon still running, the last started
# first; KILL after 10 s; returns once each has ended (1 if one would not).
stop_daemons() {
    local d name pid i stopped=() rc=0
    for ((d = ${#DAEMONS[@]} - 1; d >= 0; d--)); do
        name=${DAEMONS[d]}
        if pid=$(pid_of "$name"); then
            kill -TERM "$pid" 2>/dev/null || true
            for ((i = 0; i < 100; i++)); do
                pid_of "$name" >/dev/null || break
                sleep 0.1
            done
            if pid_of "$name" >/dev/null; then
                say "warning: $name ($pid) ignored TERM for 10 s: sending KILL"
                kill -KILL "$pid" 2>/dev/null || true
                for ((i = 0; i < 50; i++)); do
                    pid_of "$name" >/dev/null || break
                    sleep 0.1
                done
            fi
            if pid_of "$name" >/dev/null; then
                say "error: $name ($pid) is still running"
                rc=1
                continue
            fi
            stopped+=("$name($pid)")
        fi
        rm -f "$PIDS/$name.pid"
    done
    if ((${#stopped[@]})); then say "stopped ${stopped[*]}"; else say "no daemon of $DIR was running"; fi
    stop_stray_steps
    return $rc
}

# stop_stray_steps: job steps that outlived a slurmd killed with -9 (a
# slurmstepd holding this folder's slurmd.log open: ours, whatever its PID)
# are killed with every process of their session, the job's.
stop_stray_steps() {
    local p f comm sid sessions=() i left
    for p in /proc/[0-9]*; do
        read -r comm 2>/dev/null <"$p/comm" || continue
        [ "$comm" = slurmstepd ] || continue
        for f in "$p"/fd/*; do
            if [ "$(readlink "$f" 2>/dev/null)" = "$DIR/log/slurmd.log" ]; then
                sid=$(stat_word "${p#/proc/}" 4) && sessions+=("$sid")
                break
            fi
        done
    done
    ((${#sessions[@]})) || return 0
    say "killing the job steps left by a killed slurmd (sessions ${sessions[*]})"
    for ((i = 0; i < 50; i++)); do
        left=0
        for p in /proc/[0-9]*; do
            sid=$(stat_word "${p#/proc/}" 4) || continue
            [ "$(stat_word "${p#/proc/}" 1)" != Z ] || continue
            case " ${sessions[*]} " in *" $sid "*)
                kill -KILL "${p#/proc/}" 2>/dev/null || true
                left=1
                ;;
            esac
        done
        ((left)) || return 0
        sleep 0.1
    done
    say "warning: processes of sessions ${sessions[*]} still run"
}

cmd_start() {
    [ "$(id -u)" = 0 ] || die "must run as root (slurmd starts jobs as their user)"
    local t0 missing=() pair name running=0 node
    t0=$(date +%s.%N)

    # 1. Debian's packages, when missing (8 packages; slurm-wlm would pull 43).
    for pair in munged:munge slurmctld:slurmctld slurmd:slurmd sbatch:slurm-client; do
        command -v "${pair%%:*}" >/dev/null 2>&1 || missing+=("${pair#*:}")
    done
    if ((${#missing[@]})); then
        say "installing ${missing[*]}"
        export DEBIAN_FRONTEND=noninteractive
        apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null ||
            { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; } ||
            die "apt-get install ${missing[*]} failed"
    fi

    # 2. Already running: nothing to do. Partly running (a daemon died): stop
    # the rest and start afresh, so that the three agree.
    for name in "${DAEMONS[@]}"; do
        if pid_of "$name" >/dev/null; then running=$((running + 1)); fi
    done
    if ((running == ${#DAEMONS[@]})) && scontrol ping >/dev/null 2>&1; then
        say "already running; node localhost $(sinfo -h -n localhost -o '%T, %c CPUs')"
        say "use: source $DIR/env"
        return 0
    fi
    if ((running)); then
        say "partly running: restarting"
        cancel_jobs
        stop_daemons || die "cannot stop the running daemons"
    fi

    # 3. The folder and its own munge key (kept across --keep).
    ((${#SOCK} < 108)) || die "the munge socket $SOCK is longer than 107 bytes: set GLINT_SLURM_DIR to a shorter folder"
    mkdir -p "$DIR"/{etc,log,run,pids,spool/ctld,spool/d,munge/key,munge/run}
    touch "$MARK"
    chmod 755 "$DIR" "$DIR/munge" "$DIR/munge/run" # munged wants the socket's folders searchable by all
    chmod 700 "$DIR/munge/key"
    if [ ! -s "$KEY" ]; then
        mungekey --create --keyfile="$KEY" >/dev/null 2>&1 ||
            dd if=/dev/urandom of="$KEY" bs=1024 count=1 status=none
    fi
    chmod 400 "$KEY"

    # 4. slurm.conf: the node line is slurmd -C's (CPUs, cores, memory as
    # found), renamed to localhost on loopback.
    node=$(slurmd -C | head -1 | sed -E 's/^NodeName=[^ ]+/NodeName=localhost NodeAddr=127.0.0.1/')
    case $node in NodeName=localhost*CPUs=*) ;; *) die "unexpected slurmd -C output: $node" ;; esac
    cat >"$CONF" <<EOF
# Written by glint's scripts/slurm-local.sh: one node, everything as root.
ClusterName=glintlocal
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# cred_expire: how long a credential lives, and so how long a requeued
# job waits before it starts again (its begin time: cred_expire + 1 s; the
# default, 120 s, makes a requeue take minutes; 5 is the least allowed).
AuthInfo=socket=$SOCK,cred_expire=10
StateSaveLocation=$DIR/spool/ctld
SlurmdSpoolDir=$DIR/spool/d
SlurmctldPidFile=$DIR/run/slurmctld.pid
SlurmdPidFile=$DIR/run/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups (nothing under /sys/fs/cgroup): a job's processes are tracked through their parents.
ProctrackType=proctrack/linuxproc
TaskPlugin=$TASK_PLUGIN
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
# Start the next array tasks as soon as CPUs free up (the default waits 3 s).
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
# sbatch --wait polls every 2 s while MinJobAge/2 > 2 s, then every 8 or 32 s.
MinJobAge=4
KillWait=5
ReturnToService=2
$node State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF

    # 5. The daemons, each checked before the next. A failure stops those
    # already started (the folder stays, for the logs).
    trap 'rc=$?; if ((rc)); then stop_daemons || true; say "logs: $DIR/log; remove with: $0 stop"; fi' EXIT
    rm -f "$SOCK" "$SOCK.lock"
    launch munged --foreground --key-file="$KEY" --socket="$SOCK" \
        --pid-file="$DIR/run/munged.pid" --log-file="$DIR/log/munged.log" \
        --seed-file="$DIR/munge/key/munged.seed"
    wait_for munged munge_ok
    port_free "$CTLD_PORT" GLINT_SLURM_CTLD_PORT
    launch slurmctld -D -c -f "$CONF" # -c: no jobs recovered from an earlier run
    wait_for slurmctld scontrol ping
    port_free "$SLURMD_PORT" GLINT_SLURM_SLURMD_PORT
    launch slurmd -D -c -f "$CONF" -N localhost
    wait_for "node localhost (idle in sinfo)" node_idle
    for name in "${DAEMONS[@]}"; do
        pid_of "$name" >/dev/null || die "$name exited (see $DIR/log/$name.out)"
    done
    trap - EXIT

    printf 'export SLURM_CONF=%s\n' "$CONF" >"$DIR/env"
    say "started munged, slurmctld, slurmd in $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }') s; node localhost $(sinfo -h -n localhost -o '%T, %c CPUs')"
    cat >&2 <<EOF
slurm-local: use it with
    source $DIR/env
    sinfo; sbatch --array=0-3 --wait JOB.sh
and stop it with
    $0 stop
EOF
}

cmd_stop() {
    local keep=0
    case ${1:-} in --keep) keep=1 ;; "") ;; *) usage ;; esac
    cancel_jobs
    local rc=0
    stop_daemons || rc=$?
    if ((rc)); then
        say "not removing $DIR: a daemon is still running"
        return $rc
    fi
    if ((keep)) || [ ! -e "$DIR" ]; then
        [ -e "$DIR" ] && say "kept $DIR"
        return 0
    fi
    if [ -f "$MARK" ]; then
        rm -rf "$DIR"
        say "removed $DIR"
    else
        say "not removing $DIR: this script did not make it"
    fi
}

cmd_status() {
    local name pid up=0 line=()
    for name in "${DAEMONS[@]}"; do
        if pid=$(pid_of "$name"); then
            up=$((up + 1))
            line+=("$name($pid)")
        else
            line+=("$name(stopped)")
        fi
    done
    if ((up == ${#DAEMONS[@]})); then
        say "running in $DIR: ${line[*]}; node localhost $(sinfo -h -n localhost -o '%T, %c CPUs' 2>/dev/null || echo 'not answering')"
        say "use: source $DIR/env"
        return 0
    elif ((up)); then
        say "partly running in $DIR: ${line[*]} (start restarts it, stop stops it)"
        return 1
    fi
    say "not running ($DIR)"
    return 3
}

case "${1:-}:$#" in
start:1) cmd_start ;;
stop:1 | stop:2) cmd_stop "${2:-}" ;;
status:1) cmd_status ;;
*) usage ;;
esac
