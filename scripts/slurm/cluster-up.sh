#!/usr/bin/env bash
# Brings up a one-node Slurm cluster on this machine (localhost), for trying
# the job-array scripts and for the test suite: munged, slurmctld and slurmd
# from Debian's slurm-wlm and munge (scripts/install-deps.sh installs them),
# configured by a slurm.conf this script writes. Needs root. Idempotent: a
# cluster already answering is left as it is.
# Usage: scripts/slurm/cluster-up.sh   (scripts/slurm/cluster-down.sh stops it)
set -euo pipefail
if [ "$(id -u)" -ne 0 ]; then
  echo "cluster-up: needs root (it starts munged, slurmctld and slurmd)" >&2
  exit 1
fi
for tool in munged slurmctld slurmd sinfo; do
  command -v "$tool" >/dev/null || { echo "cluster-up: $tool is missing (apt-get install slurm-wlm munge)" >&2; exit 1; }
done
if sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
  echo "cluster-up: a cluster is already up"
  exit 0
fi

cpus=$(nproc)
memory=$(($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 * 9 / 10))
state=/var/lib/wavepath-slurm  # state and spool: a filesystem that allows execution
mkdir -p "$state/ctld" "$state/d" /var/log/slurm /run/munge
chown slurm:slurm "$state/ctld" /var/log/slurm
chown munge:munge /run/munge

# Only a slurm.conf this script wrote is replaced; another is the site's.
conf=/etc/slurm/slurm.conf
marker="# written by wavepath scripts/slurm/cluster-up.sh"
if [ -e "$conf" ] && ! grep -qF "$marker" "$conf"; then
  echo "cluster-up: $conf exists and is not ours; not touching it" >&2
  exit 1
fi
mkdir -p /etc/slurm
cat >"$conf" <<CONF
$marker
ClusterName=wavepath
SlurmctldHost=localhost
AuthType=auth/munge
CryptoType=crypto/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
ReturnToService=2
SlurmUser=slurm
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/d
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
KillWait=10
# A job asks for its CPUs' share of the memory unless it says otherwise
# (without this, each would get the whole node and run alone).
DefMemPerCPU=$((memory / cpus))
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=main Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF

[ -s /etc/munge/munge.key ] || { dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=128 status=none; chown munge:munge /etc/munge/munge.key; chmod 400 /etc/munge/munge.key; }
pgrep -x munged >/dev/null || runuser -u munge -- /usr/sbin/munged
pgrep -x slurmctld >/dev/null || slurmctld
pgrep -x slurmd >/dev/null || slurmd -N localhost

for _ in $(seq 60); do
  if sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
    echo "cluster-up: one node (localhost, $cpus CPUs) is up; sinfo and sbatch are ready"
    exit 0
  fi
  sleep 0.5
done
echo "cluster-up: the node did not come up in 30 s; see /var/log/slurm/slurmctld.log and slurmd.log" >&2
exit 1
