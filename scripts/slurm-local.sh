#!/usr/bin/env bash
# Slurm on this one machine, to try `ancf sweep --executor slurm` without a
# cluster.
#
#   sudo bash scripts/slurm-local.sh start    # install, configure, start
#   bash scripts/slurm-local.sh status        # sinfo and the queue
#   sudo bash scripts/slurm-local.sh stop     # stop the daemons
#
# `start` installs Debian's slurm-wlm and munge when they are missing,
# writes a single-node configuration for this machine (its CPUs and memory
# as `slurmd -C` reports them, one partition `local`, no accounting
# database: job states come from scontrol), starts munged, slurmctld and
# slurmd, and waits until the node is idle. Everything Slurm writes goes to
# /var/spool/slurm-local (logs there too). A real cluster needs none of
# this: run the same `ancf sweep` on its login node (docs/sweep.md).
set -euo pipefail

spool=/var/spool/slurm-local
conf=/etc/slurm/slurm.conf

need_root() {
    if [ "$(id -u)" != 0 ]; then
        echo "slurm-local: '$1' needs root (it installs packages and starts daemons)" >&2
        exit 1
    fi
}

start() {
    need_root start
    if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
        echo "slurm-local: installing slurm-wlm and munge"
        apt-get update -q
        DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge
    fi
    # munge: a key, its directories, the daemon.
    mkdir -p /etc/munge /run/munge /var/lib/munge /var/log/munge
    if [ ! -s /etc/munge/munge.key ]; then
        mungekey --create --keyfile=/etc/munge/munge.key
    fi
    chown -R munge:munge /etc/munge /run/munge /var/lib/munge /var/log/munge
    chmod 0700 /etc/munge
    chmod 0400 /etc/munge/munge.key
    if ! pgrep -x munged >/dev/null; then
        runuser -u munge -- /usr/sbin/munged
    fi
    # The configuration for this machine.
    host=$(hostname -s)
    node=$(slurmd -C | head -n 1 | sed "s/^NodeName=[^ ]*/NodeName=$host/")
    mkdir -p "$spool/ctld" "$spool/d" /etc/slurm
    cat >"$conf" <<EOF
# Written by ancf's scripts/slurm-local.sh: one node, no accounting database.
ClusterName=ancf-local
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$spool/ctld
SlurmdSpoolDir=$spool/d
SlurmctldPidFile=$spool/slurmctld.pid
SlurmdPidFile=$spool/slurmd.pid
SlurmctldLogFile=$spool/slurmctld.log
SlurmdLogFile=$spool/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MinJobAge=3600
MaxArraySize=10001
InactiveLimit=0
KillWait=10
$node State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
    pgrep -x slurmctld >/dev/null || slurmctld
    pgrep -x slurmd >/dev/null || slurmd
    for _ in $(seq 1 60); do
        state=$(sinfo -h -o %T 2>/dev/null | head -n 1 || true)
        if [ "$state" = idle ]; then
            echo "slurm-local: node $host idle ($node)"
            return 0
        fi
        sleep 1
    done
    echo "slurm-local: the node did not become idle; see $spool/slurmctld.log and $spool/slurmd.log" >&2
    sinfo -R >&2 || true
    exit 1
}

stop() {
    need_root stop
    scancel --user=root 2>/dev/null || true
    pkill -x slurmd 2>/dev/null || true
    pkill -x slurmctld 2>/dev/null || true
    pkill -x munged 2>/dev/null || true
    echo "slurm-local: stopped"
}

status() {
    sinfo
    squeue
}

case "${1:-}" in
start) start ;;
stop) stop ;;
status) status ;;
*)
    echo "usage: $0 start|stop|status" >&2
    exit 2
    ;;
esac
