#!/usr/bin/env bash
# slurm_check.sh CONFIG: runs the workflow of CONFIG through a real single-node Slurm cluster and
# on this machine alone, and exits 0 only when both made the same products (compare_runs.py).
#
# The cluster lives under a temporary folder: munged with its own key and socket, slurmctld and
# slurmd from a generated slurm.conf (unprivileged ports, state, spool, logs and PID files there),
# all as the current user. Every daemon started here is stopped by its PID when the script ends,
# however it ends. Where Slurm cannot start (not installed, no munge, the daemons refuse this
# machine) it prints "skipped: WHY" and exits 77, which ctest reports as a skip.
#
# Run it where CONFIG's relative paths start (as snakemake). The products of both runs go to
# outdir/slurm and outdir/local (CONFIG's outdir, else a folder under the temporary one). VDBFUSE_SLURM_KEEP=1 keeps the temporary folder to read the logs.
set -euo pipefail
readonly SKIP=77
here=$(cd "$(dirname "$0")" && pwd)
config=${1:?usage: slurm_check.sh CONFIG}
[ -f "$config" ] || { echo "slurm_check.sh: $config: no such config" >&2; exit 1; }
config=$(cd "$(dirname "$config")" && pwd)/$(basename "$config")

skip() {
  echo "skipped: $*"
  exit "$SKIP"
}

for tool in munged slurmctld slurmd sbatch srun scontrol sinfo snakemake python3; do
  command -v "$tool" >/dev/null || skip "$tool is not installed (Debian: apt-get install slurm-wlm munge snakemake)"
done

tmp=$(mktemp -d "${TMPDIR:-/tmp}/vdbfuse-slurm.XXXXXX")
chmod 700 "$tmp"
daemon_pids=()
stop_daemons() {
  local status=$?
  # slurmd first (it ends the job steps it runs), then the controller, then munge.
  for ((i = ${#daemon_pids[@]} - 1; i >= 0; i--)); do kill -TERM "${daemon_pids[i]}" 2>/dev/null || true; done
  for pid in "${daemon_pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then
      echo "slurm_check: daemon $pid ignored SIGTERM for 5 s; killing it" >&2
      kill -KILL "$pid" 2>/dev/null || true
    fi
  done
  if [ "${VDBFUSE_SLURM_KEEP:-0}" = 1 ]; then echo "slurm_check: kept $tmp"; else rm -rf "$tmp"; fi
  exit "$status"
}
trap stop_daemons EXIT
trap 'exit 130' INT TERM

user=$(id -un)
export USER=$user  # Snakemake's Slurm executor reads it
host=$(hostname -s)

# munge: a key of this cluster's own, a socket only its daemons use.
mkdir -p "$tmp/munge"
chmod 700 "$tmp/munge"
head -c 1024 /dev/urandom >"$tmp/munge/munge.key"
chmod 400 "$tmp/munge/munge.key"
munged --foreground --force --key-file="$tmp/munge/munge.key" --socket="$tmp/munge/munge.socket" \
  --pid-file="$tmp/munge/munged.pid" --log-file="$tmp/munge/munged.log" --seed-file="$tmp/munge/munge.seed" \
  >"$tmp/munge/stdout.log" 2>&1 &
daemon_pids+=($!)
for _ in $(seq 50); do [ -S "$tmp/munge/munge.socket" ] && break; sleep 0.1; done
if [ ! -S "$tmp/munge/munge.socket" ]; then
  skip "munged did not start: $(tail -n 2 "$tmp/munge/munged.log" "$tmp/munge/stdout.log" 2>/dev/null | tr '\n' ' ')"
fi

# Two free TCP ports above 1024 for slurmctld and slurmd.
read -r ctld_port slurmd_port < <(python3 -c '
import socket
ports = []
holders = [socket.socket() for _ in range(2)]
for s in holders:
    s.bind(("127.0.0.1", 0))
    ports.append(s.getsockname()[1])
print(*ports)')
cpus=$(nproc)
memory_mb=$(awk '/MemTotal/ {print int($2 / 1024 * 0.8)}' /proc/meminfo)
mkdir -p "$tmp/state" "$tmp/spool" "$tmp/log"
cat >"$tmp/slurm.conf" <<EOF
# A one-node cluster for workflow/slurm_check.sh; everything under $tmp.
ClusterName=vdbfusecheck
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
# No cgroups, no accounting daemon: what a container or a bare VM offers.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge=600
KillWait=5
InactiveLimit=0
NodeName=vfnode NodeHostname=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=check Nodes=vfnode Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$tmp/slurm.conf

slurmctld -D -i -f "$SLURM_CONF" >"$tmp/log/slurmctld.stdout" 2>&1 &
daemon_pids+=($!)
slurmd -D -N vfnode -f "$SLURM_CONF" >"$tmp/log/slurmd.stdout" 2>&1 &
daemon_pids+=($!)
state=""
for _ in $(seq 60); do
  state=$(sinfo -h -n vfnode -o %T 2>/dev/null || true)
  case $state in idle*|mixed*|allocated*) break ;; esac
  for pid in "${daemon_pids[@]}"; do
    kill -0 "$pid" 2>/dev/null || skip "a Slurm daemon (PID $pid) exited: $(tail -n 3 "$tmp"/log/*.log "$tmp"/log/*.stdout 2>/dev/null | tr '\n' ' ')"
  done
  sleep 0.5
done
case $state in
  idle*|mixed*|allocated*) ;;
  *) skip "the node did not come up within 30 s (state '${state:-none}'): $(tail -n 3 "$tmp"/log/*.log 2>/dev/null | tr '\n' ' ')" ;;
esac
# One job through the scheduler before the workflow: a node that cannot run jobs skips here.
if ! probe=$(timeout 60 srun -N1 -n1 -t 1 echo ran-on-slurm 2>&1) || [ "$probe" != ran-on-slurm ]; then
  skip "the node does not run jobs: $probe $(tail -n 3 "$tmp/log/slurmd.log" 2>/dev/null | tr '\n' ' ')"
fi
echo "slurm_check: cluster up (node vfnode, $cpus CPUs, $memory_mb MB; ports $ctld_port, $slurmd_port)"

outdir=$(python3 -c 'import sys, yaml; print((yaml.safe_load(open(sys.argv[1])) or {}).get("outdir") or "")' "$config")
[ -n "$outdir" ] || outdir=$tmp/products
mkdir -p "$outdir"
outdir=$(cd "$outdir" && pwd)
snakefile=$here/Snakefile

# The cluster run first: a reused outdir/slurm must be made again by the scheduler's jobs. Both
# run here, where CONFIG's relative paths are meant (as for snakemake itself).
rm -rf "$outdir/slurm" "$outdir/local"
slurm_status=0
snakemake -s "$snakefile" --profile "$here/profiles/slurm" --configfile "$config" \
  --config outdir="$outdir/slurm" >"$outdir/slurm.log" 2>&1 || slurm_status=$?
local_status=0
snakemake -s "$snakefile" --cores "$cpus" --keep-going --configfile "$config" \
  --config outdir="$outdir/local" >"$outdir/local.log" 2>&1 || local_status=$?
echo "slurm_check: workflow through Slurm exited $slurm_status (log $outdir/slurm.log), locally $local_status (log $outdir/local.log)"
jobs_run=$(grep -c "has been submitted with SLURM jobid" "$outdir/slurm.log" || true)
echo "slurm_check: $jobs_run jobs went through sbatch"
if [ "$slurm_status" != "$local_status" ]; then
  tail -n 30 "$outdir/slurm.log"
  echo "slurm_check: FAILED: the two runs ended differently"
  exit 1
fi
if [ "$jobs_run" -eq 0 ]; then
  echo "slurm_check: FAILED: no job was submitted to Slurm"
  exit 1
fi
if python3 "$here/scripts/compare_runs.py" "$outdir/slurm" "$outdir/local"; then
  echo "slurm_check: the Slurm and the local run made the same products"
else
  echo "slurm_check: FAILED: the products differ"
  exit 1
fi
