# A single-node Slurm on localhost for tests and benchmarks: munge, slurmctld
# and slurmd started as root with their own configuration in a folder of
# their own (nothing in /etc is changed), and stopped by their PIDs.
# Needs `scripts/install-deps.sh --slurm`. Source this file, then:
#   slurm_local_start DIR || skip    # exports SLURM_CONF; returns 1 with a reason on stderr
#   ... sbatch, squeue, plumage batch --slurm ...
#   slurm_local_stop DIR
# docs/batch.md ("A single-node Slurm, for tests") describes it.

slurm_local_start() {
    local dir=$1 cpus
    for tool in munged munge slurmctld slurmd sbatch squeue sinfo scancel; do
        command -v "$tool" >/dev/null || { echo "slurm: $tool is not installed (scripts/install-deps.sh --slurm)" >&2; return 1; }
    done
    [ "$(id -u)" -eq 0 ] || { echo "slurm: the daemons must be started as root" >&2; return 1; }
    mkdir -p "$dir/state" "$dir/spool" "$dir/log"
    dir=$(cd "$dir" && pwd)
    # munge: reuse a running daemon, else start one (it refuses to run as root).
    if ! munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1; then
        [ -s /etc/munge/munge.key ] || mungekey --create >/dev/null 2>&1 || { echo "slurm: no munge key" >&2; return 1; }
        install -d -o munge -g munge -m 0755 /run/munge
        runuser -u munge -- /usr/sbin/munged || { echo "slurm: munged did not start" >&2; return 1; }
        echo started > "$dir/munged.ours"
    fi
    cpus=$(nproc)
    # Ports of our own, so that another Slurm on the machine is left alone.
    local port=$((20000 + ($$ % 5000) * 2))
    cat > "$dir/slurm.conf" <<CONF
ClusterName=plumage
SlurmctldHost=localhost
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
MailProg=/bin/true
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerParameters=batch_sched_delay=0
KillWait=5
ReturnToService=2
NodeName=localhost CPUs=$cpus RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
    export SLURM_CONF=$dir/slurm.conf
    slurmctld -f "$SLURM_CONF" || { echo "slurm: slurmctld did not start (see $dir/log)" >&2; slurm_local_stop "$dir"; return 1; }
    slurmd -f "$SLURM_CONF" -N localhost || { echo "slurm: slurmd did not start (see $dir/log)" >&2; slurm_local_stop "$dir"; return 1; }
    for _ in $(seq 300); do
        sinfo -h -o %t 2>/dev/null | grep -qx idle && return 0
        sleep 0.1
    done
    echo "slurm: the node did not become idle within 30 s (see $dir/log)" >&2
    slurm_local_stop "$dir"
    return 1
}

slurm_local_stop() {
    local dir=$1 pid
    for f in slurmd slurmctld; do
        if [ -s "$dir/$f.pid" ]; then
            pid=$(cat "$dir/$f.pid")
            kill "$pid" 2>/dev/null
            for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
            rm -f "$dir/$f.pid"
        fi
    done
    if [ -e "$dir/munged.ours" ] && [ -s /run/munge/munged.pid ]; then
        kill "$(cat /run/munge/munged.pid)" 2>/dev/null
        rm -f "$dir/munged.ours"
    fi
}
