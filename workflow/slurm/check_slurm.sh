#!/usr/bin/env bash
# Opt-in check that the workflow runs on SLURM through snakemake-executor-plugin-slurm, with
# the shipped profile (workflow/profiles/slurm), on a single-node SLURM cluster started here
# from Debian's slurm-wlm and munge packages. Not part of the default tests.
#
#   bash workflow/slurm/check_slurm.sh            # needs root, slurm-wlm, munge, the plugin
#   bash workflow/slurm/check_slurm.sh --install  # first install what is missing (apt-get, make install)
#
# What it does: writes a one-node slurm.conf (this host, all its CPUs) into a scratch
# directory, starts munged, slurmctld and slurmd (and stops exactly those on exit), checks
# `srun`, then runs `snakemake --workflow-profile workflow/profiles/slurm map2d` in a scratch
# copy of the working directory with a tiny 2-D map (workflow/slurm/check_config.yaml), and
# checks that the map was built and that every job went through sbatch. Exit 0 = pass.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
VENV="${VENV:-$REPO/.venv}"
SCRATCH="${SCRATCH:-/tmp/impactosc-slurm-check}"
INSTALL=0
[[ "${1:-}" == "--install" ]] && INSTALL=1

say() { printf '[check_slurm] %s\n' "$*"; }
die() { say "FAIL: $*"; exit 1; }

[[ $(id -u) -eq 0 ]] || die "run as root (the check starts slurmctld, slurmd and munged)"
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    [[ $INSTALL -eq 1 ]] || die "slurm-wlm/munge missing: apt-get install -y slurm-wlm munge (or pass --install)"
    apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y slurm-wlm munge
fi
if ! "$VENV/bin/python" -c "import snakemake_executor_plugin_slurm" 2>/dev/null; then
    # the plugin is in requirements.lock (the slurm extra): make installs it
    [[ $INSTALL -eq 1 ]] || die "the SLURM executor plugin is missing from $VENV: run make install in $REPO"
    make -C "$REPO" install
fi

HOST="$(hostname -s)"
CPUS="$(nproc)"
MEM_MB="$(awk '/MemTotal/ {print int($2 / 1024 * 0.8)}' /proc/meminfo)"
rm -rf "$SCRATCH"
mkdir -p "$SCRATCH"/{state,spool,log,run,munge,work}
CONF="$SCRATCH/slurm.conf"
cat > "$CONF" <<EOF
ClusterName=impactosc-check
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CryptoType=crypto/munge
AuthInfo=socket=$SCRATCH/munge/munge.socket
StateSaveLocation=$SCRATCH/state
SlurmdSpoolDir=$SCRATCH/spool
SlurmctldPidFile=$SCRATCH/run/slurmctld.pid
SlurmdPidFile=$SCRATCH/run/slurmd.pid
SlurmctldLogFile=$SCRATCH/log/slurmctld.log
SlurmdLogFile=$SCRATCH/log/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
MpiDefault=none
ReturnToService=2
MinJobAge=3600
NodeName=$HOST CPUs=$CPUS RealMemory=$MEM_MB State=UNKNOWN
PartitionName=check Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$CONF"
# Job steps (srun inside the sbatch jobs) look for the default path, not SLURM_CONF: put the
# file there for the duration of the check, unless a real cluster's configuration is present.
SYS_CONF=/etc/slurm/slurm.conf
if [[ -e "$SYS_CONF" ]] && ! grep -q '^ClusterName=impactosc-check' "$SYS_CONF"; then
    die "$SYS_CONF exists and is not ours: this machine already has a SLURM configuration"
fi
mkdir -p /etc/slurm
cp "$CONF" "$SYS_CONF"

cleanup() {
    local pids=()
    for pidfile in "$SCRATCH/run/slurmd.pid" "$SCRATCH/run/slurmctld.pid" "$SCRATCH/run/munged.pid"; do
        [[ -s "$pidfile" ]] && pids+=("$(cat "$pidfile")")
    done
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    for _ in $(seq 20); do  # slurmctld saves its state before it exits
        alive=0
        for pid in "${pids[@]}"; do kill -0 "$pid" 2>/dev/null && alive=1; done
        [[ $alive -eq 0 ]] && break
        sleep 0.5
    done
    grep -q '^ClusterName=impactosc-check' "$SYS_CONF" 2>/dev/null && rm -f "$SYS_CONF"
    return 0
}
trap cleanup EXIT

say "starting munged, slurmctld, slurmd ($HOST, $CPUS CPUs, $MEM_MB MB)"
chown -R munge:munge "$SCRATCH/munge" 2>/dev/null || true
/usr/sbin/munged --socket="$SCRATCH/munge/munge.socket" --pid-file="$SCRATCH/run/munged.pid" \
    --log-file="$SCRATCH/log/munged.log" --seed-file="$SCRATCH/munge/munge.seed" --force
/usr/sbin/slurmctld -f "$CONF"
/usr/sbin/slurmd -f "$CONF"
for _ in $(seq 60); do
    state="$(sinfo -h -n "$HOST" -o %t 2>/dev/null || true)"
    [[ "$state" == idle* ]] && break
    sleep 1
done
[[ "$state" == idle* ]] || die "node did not come up (state '$state'); see $SCRATCH/log"
say "node $HOST is $state; srun: $(srun -N1 -n1 hostname)"

# A scratch working directory with the repository's config and a tiny map on top of it.
mkdir -p "$SCRATCH/work/config"
cp "$REPO/config/config.yaml" "$SCRATCH/work/config/config.yaml"
export NUMBA_CACHE_DIR="${NUMBA_CACHE_DIR:-$REPO/.numba_cache}"  # reuse the compiled core
cd "$SCRATCH/work"
say "snakemake --workflow-profile workflow/profiles/slurm map2d (tiny map)"
start=$(date +%s)
"$VENV/bin/snakemake" -s "$REPO/Snakefile" --workflow-profile "$REPO/workflow/profiles/slurm" \
    --configfile "$SCRATCH/work/config/config.yaml" "$REPO/workflow/slurm/check_config.yaml" \
    --slurm-no-account --slurm-status-command squeue --slurm-keep-successful-logs \
    --slurm-init-seconds-before-status-checks 5 --jobs "$CPUS" map2d 2>&1 | tee "$SCRATCH/log/snakemake.log"
took=$(( $(date +%s) - start ))
[[ -s results/paper/figures/bifurcation/map2d.png && -s results/paper/runs/bifurcation/map2d.h5 ]] || die "map2d outputs missing"
n_jobs="$(grep -c 'Job .* has been submitted with SLURM jobid' "$SCRATCH/log/snakemake.log" || true)"
n_done="$(squeue -h -t all -o '%i %T' | grep -c COMPLETED || true)"
[[ "$n_jobs" -ge 3 ]] || die "expected the map's jobs to be submitted through sbatch, saw $n_jobs"
say "PASS: map2d built on SLURM in ${took} s: $n_jobs jobs submitted with sbatch, $n_done listed COMPLETED by squeue"
say "logs: $SCRATCH/log, SLURM job logs: $SCRATCH/work/.snakemake/slurm_logs"
