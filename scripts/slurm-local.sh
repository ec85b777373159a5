#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for the tests of fvx batch's Slurm path:
#   scripts/slurm-local.sh start DIR   # munged (if not running), slurmctld and slurmd; prints SLURM_CONF
#   scripts/slurm-local.sh stop DIR    # stops what start started, removes DIR
# Needs root and Debian's slurm-wlm and munge (scripts/install-deps.sh). Everything lives in
# DIR (configuration, state, spool, logs); ports 6917 and 6918, not Slurm's defaults, so that
# a real Slurm on the machine is left alone. The node is this host with all its cores.
set -euo pipefail

action=${1:-}
dir=${2:-}
[ -n "$action" ] && [ -n "$dir" ] || { echo "usage: slurm-local.sh start|stop DIR" >&2; exit 2; }

stop() {
  SLURM_CONF="$dir/slurm.conf" scancel --quiet --user=root 2>/dev/null || true
  local pids="" alive
  for daemon in slurmd slurmctld munged; do  # munged.pid only when start started it
    [ -f "$dir/$daemon.pid" ] && pids="$pids $(cat "$dir/$daemon.pid")"
  done
  [ -n "$pids" ] && kill $pids 2>/dev/null
  for _ in $(seq 1 50); do  # slurmctld saves its state first: up to 10 s, then killed
    alive=""
    for pid in $pids; do kill -0 "$pid" 2>/dev/null && alive=1; done
    [ -z "$alive" ] && break
    sleep 0.2
  done
  [ -n "$alive" ] && kill -9 $pids 2>/dev/null
  rm -rf "$dir"
}

start() {
  [ "$(id -u)" -eq 0 ] || { echo "slurm-local.sh: needs root (slurmd runs jobs as their users)" >&2; exit 1; }
  for tool in slurmctld slurmd sbatch munged; do
    command -v "$tool" >/dev/null || { echo "slurm-local.sh: $tool is missing (scripts/install-deps.sh)" >&2; exit 1; }
  done
  mkdir -p "$dir"/{state,spool,log}
  if ! munge -n >/dev/null 2>&1; then  # no munged answering: start one and stop it later
    mkdir -p /run/munge && chown munge:munge /run/munge
    [ -f /etc/munge/munge.key ] || { echo "slurm-local.sh: /etc/munge/munge.key is missing" >&2; exit 1; }
    runuser -u munge -- /usr/sbin/munged 2>"$dir/log/munged.err" ||
      { echo "slurm-local.sh: munged did not start: $(head -1 "$dir/log/munged.err")" >&2; exit 1; }
    pgrep -n -x munged > "$dir/munged.pid"
  fi
  local host; host=$(hostname -s)
  cat > "$dir/slurm.conf" <<EOF
ClusterName=fvxlocal
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
SlurmctldPort=6917
SlurmdPort=6918
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=fvx Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  slurmctld -f "$dir/slurm.conf" || { echo "slurm-local.sh: slurmctld did not start (see $dir/log)" >&2; exit 1; }
  slurmd -f "$dir/slurm.conf" || { echo "slurm-local.sh: slurmd did not start (see $dir/log)" >&2; exit 1; }
  for _ in $(seq 1 100); do  # up to 20 s for the node to report idle
    if SLURM_CONF="$dir/slurm.conf" sinfo -h -o %t 2>/dev/null | grep -q idle; then
      echo "$dir/slurm.conf"
      return 0
    fi
    sleep 0.2
  done
  echo "slurm-local.sh: the node did not become idle: $(tail -1 "$dir/log/slurmctld.log" 2>/dev/null)" >&2
  exit 1
}

case "$action" in
  start) start ;;
  stop) stop ;;
  *) echo "usage: slurm-local.sh start|stop DIR" >&2; exit 2 ;;
esac
