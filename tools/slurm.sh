#!/usr/bin/env bash
# A one-machine Slurm cluster for the farm tests: `tools/slurm.sh start`
# installs Debian's slurm-wlm and munge if missing, writes a configuration
# under tools/.slurm (SLURM_CONF points there), starts munged, slurmctld and
# slurmd, and waits until the node takes jobs; `tools/slurm.sh stop` stops
# them. Prints the SLURM_CONF to export. Needs root (as CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
state="$PWD/tools/.slurm"
conf="$state/slurm.conf"

start() {
  if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    echo "installing slurm-wlm and munge (Debian)" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge >&2
  fi
  mkdir -p "$state/spool/ctld" "$state/spool/d" "$state/log"
  local host cpus mem
  host="$(hostname -s)"
  cpus="$(nproc)"
  mem="$(awk '/MemTotal/ {print int($2 / 1024) - 512}' /proc/meminfo)"
  cat > "$conf" <<EOF
ClusterName=geode
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
StateSaveLocation=$state/spool/ctld
SlurmdSpoolDir=$state/spool/d
SlurmctldLogFile=$state/log/slurmctld.log
SlurmdLogFile=$state/log/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
MaxArraySize=10001
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=geode Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  mkdir -p /run/munge /var/log/munge /var/lib/munge
  chown munge:munge /run/munge /var/log/munge /var/lib/munge 2>/dev/null || true
  if ! pgrep -x munged >/dev/null; then
    if [ ! -s /etc/munge/munge.key ]; then mungekey --create >&2 || true; fi
    runuser -u munge -- /usr/sbin/munged >&2 || /usr/sbin/munged --force >&2
  fi
  export SLURM_CONF="$conf"
  pgrep -x slurmctld >/dev/null || slurmctld -f "$conf"
  pgrep -x slurmd >/dev/null || slurmd -f "$conf"
  for _ in $(seq 1 60); do
    if sinfo -h -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)'; then
      echo "$conf"
      return 0
    fi
    scontrol update NodeName="$host" State=RESUME >/dev/null 2>&1 || true
    sleep 1
  done
  echo "slurm did not come up; logs in $state/log" >&2
  tail -20 "$state/log/"*.log >&2 || true
  return 1
}

stop() {
  pkill -x slurmd 2>/dev/null || true
  pkill -x slurmctld 2>/dev/null || true
  pkill -x munged 2>/dev/null || true
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  *) echo "usage: tools/slurm.sh start|stop" >&2; exit 2 ;;
esac
