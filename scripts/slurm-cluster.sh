#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the tests that run the
# Slurm recipes of docs/distributed.md and docs/grading.md (tests/slurm.rs).
#
#   scripts/slurm-cluster.sh start DIR   start it, with all its state in DIR
#   scripts/slurm-cluster.sh stop DIR    cancel its jobs and stop its daemons
#
# `start` writes DIR/slurm.conf for this host (one node, named by
# `hostname`, with 2 CPUs, in one partition), a MUNGE key for it alone, and
# starts munged (as user munge, on a socket in DIR, so that it cannot clash
# with a system munged), slurmctld and slurmd (as root, on two free ports of
# the loopback address, outside the range the kernel gives connections),
# then waits until the node is idle. Nothing is written outside DIR: the
# conf, keys, sockets, pid files, logs, the controller's state and the
# node's spool are all in it. Point the Slurm commands at the cluster with
# `SLURM_CONF=DIR/slurm.conf` (the jobs inherit it too). When `start`
# fails, it prints the daemons' logs and stops what it started.
#
# `stop` cancels every job of the cluster, waits for them to end, and stops
# each daemon by the pid in its pid file (TERM, then KILL after 10 s). It
# may run more than once and after a `start` that failed half-way. No
# systemd is needed. Run as root: the daemons and the jobs run as root,
# munged as user munge. Needs Debian's `slurm-wlm` and `munge`.
set -euo pipefail

usage() {
    echo "usage: $0 start|stop DIR" >&2
    exit 2
}
[ $# -eq 2 ] || usage
action=$1
dir=$(cd "$2" && pwd)
conf=$dir/slurm.conf
export SLURM_CONF=$conf

# The name and pid file of each daemon.
daemons=(
    "slurmd $dir/slurmd.pid"
    "slurmctld $dir/slurmctld.pid"
    "munged $dir/munge/munged.pid"
)

# The pid in pid file $2 when it is that of a running process named $1
# (a pid reused by another program is not ours to stop), by the kernel's
# name for the process.
daemon_pid() {
    local name=$1 pidfile=$2 pid
    [ -s "$pidfile" ] || return 0
    pid=$(cat "$pidfile")
    if [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$name" ]; then
        echo "$pid"
    fi
}

stop() {
    # The jobs first: their processes are slurmd's children's, and would
    # outlive the daemons (KillWait in the conf bounds how long one may
    # take to end after its TERM).
    if [ -n "$(daemon_pid slurmctld "$dir/slurmctld.pid")" ]; then
        scancel --quiet --user="$(id -un)" 2>/dev/null || true
        local deadline=$((SECONDS + 10))
        while ((SECONDS < deadline)); do
            # squeue lists the jobs that have not ended (pending, running,
            # completing).
            [ -z "$(squeue --noheader 2>/dev/null || true)" ] && break
            sleep 0.1
        done
    fi
    # TERM to every daemon at once (each takes a second or two to end),
    # then KILL to any still running after 10 s.
    local daemon pids=() pid deadline
    for daemon in "${daemons[@]}"; do
        # shellcheck disable=SC2086 # the name and the pid file
        pid=$(daemon_pid $daemon)
        if [ -n "$pid" ] && kill -TERM "$pid" 2>/dev/null; then
            pids+=("$pid")
        fi
    done
    deadline=$((SECONDS + 10))
    for pid in "${pids[@]}"; do
        while [ -d "/proc/$pid" ] && ((SECONDS < deadline)); do
            sleep 0.1
        done
        if [ -d "/proc/$pid" ]; then
            echo "$(cat "/proc/$pid/comm" 2>/dev/null) ($pid) did not stop in 10 s: killing it" >&2
            kill -KILL "$pid" 2>/dev/null || true
        fi
    done
}

# Print each daemon's log, for a start that failed.
logs() {
    local log
    for log in "$dir/munge/munged.log" "$dir/slurmctld.log" "$dir/slurmd.log"; do
        if [ -f "$log" ]; then
            echo "--- $log" >&2
            tail -n 40 "$log" >&2
        fi
    done
}

# A TCP port between 20000 and 65535 that no socket uses, in any state,
# other than $1, and outside the kernel's range for the local ends of
# connections (ip_local_port_range, 32768-60999 by default): a port in
# that range can be taken between this check and the daemon's bind by any
# connection made on the machine, and then the daemon cannot listen on it
# ("Address already in use"). Only when that range covers every port from
# 20000 up is a port inside it taken.
free_port() {
    local low=32768 high=60999 port used outside=0
    read -r low high </proc/sys/net/ipv4/ip_local_port_range || true
    ((low > 20000 || high < 65535)) && outside=1
    used=$(ss -Htan 2>/dev/null | awk '{ sub(/.*:/, "", $4); print $4 }')
    while :; do
        port=$((20000 + (RANDOM * 32768 + RANDOM) % 45536))
        [ "$port" != "${1:-}" ] || continue
        if ((outside)) && ((port >= low && port <= high)); then
            continue
        fi
        grep -qx "$port" <<<"$used" || break
    done
    echo "$port"
}

# `start` runs as the condition of an `if`, where `set -e` does not apply:
# each step that can fail returns.
start() {
    local host ctld_port slurmd_port state
    host=$(hostname) || return 1
    # The munge user must reach its folder inside DIR.
    chmod 755 "$dir" || return 1
    mkdir -p "$dir/munge" "$dir/state" "$dir/spool" || return 1
    # munged wants its socket's folder open to every user (the socket is
    # how they ask it for credentials), and nothing in it writable but by
    # itself.
    chmod 755 "$dir/munge" || return 1
    chmod 700 "$dir/state" "$dir/spool" || return 1

    # A key for this cluster alone, readable only by munged's user.
    mungekey --create --keyfile="$dir/munge/munge.key" || return 1
    chown -R munge:munge "$dir/munge" || return 1
    chmod 400 "$dir/munge/munge.key" || return 1
    runuser -u munge -- munged \
        --socket="$dir/munge/munge.socket.2" \
        --key-file="$dir/munge/munge.key" \
        --pid-file="$dir/munge/munged.pid" \
        --log-file="$dir/munge/munged.log" \
        --seed-file="$dir/munge/munged.seed" \
        </dev/null >/dev/null 2>&1 || return 1
    if ! munge --socket="$dir/munge/munge.socket.2" --no-input </dev/null |
        unmunge --socket="$dir/munge/munge.socket.2" >/dev/null; then
        echo "munged does not answer on $dir/munge/munge.socket.2" >&2
        return 1
    fi

    ctld_port=$(free_port)
    slurmd_port=$(free_port "$ctld_port")
    cat >"$conf" <<EOF
# A one-node cluster written by scripts/slurm-cluster.sh; all of its state
# is in this folder.
ClusterName=raytracer-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
# Bind to the addresses above (the loopback), not to every interface.
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# A requeued job waits for the credentials of its last run to expire:
# 10 s here, not 120.
AuthInfo=socket=$dir/munge/munge.socket.2,cred_expire=10
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
# No cgroups, no systemd: processes are tracked by their parents, and
# tasks are not bound to cores.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
# Cores are what jobs ask for and are given.
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
# No accounting database.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
# A job's KILL follows its TERM after 2 s; ended jobs stay visible to
# squeue and scontrol for 5 minutes.
KillWait=2
MinJobAge=300
ReturnToService=2
# Jobs are scheduled every second (a requeued job whose wait is over, a
# dependency met), not every 30 or 60 s, and batch jobs as soon as they
# are submitted, not up to 3 s later.
SchedulerParameters=batch_sched_delay=0,sched_interval=1,bf_interval=1
# The node has 2 CPUs whatever the machine has.
SlurmdParameters=config_overrides
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=main Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
    [ -s "$conf" ] || return 1

    slurmctld -i </dev/null >/dev/null 2>&1 || return 1
    slurmd </dev/null >/dev/null 2>&1 || return 1

    # Wall-clock seconds, not a count of tries: an sinfo that cannot reach
    # the controller waits for its own timeout.
    local deadline=$((SECONDS + 30))
    while ((SECONDS < deadline)); do
        state=$(sinfo --noheader --nodes="$host" --format=%T 2>/dev/null || true)
        [ "$state" = idle ] && return 0
        sleep 0.1
    done
    echo "the node did not become idle in 30 s (state: ${state:-unknown})" >&2
    return 1
}

case $action in
start)
    if ! start; then
        logs
        stop
        exit 1
    fi
    echo "SLURM_CONF=$conf"
    ;;
stop)
    stop
    ;;
*)
    usage
    ;;
esac
