#!/usr/bin/env bash
# A sweep through a real Slurm cluster of one node, started here: munged and slurmctld/slurmd
# from a configuration in a fresh folder (their own ports and sockets, nothing of the system's
# Slurm touched). A 64-case sweep is submitted with `hilrig sweep --slurm --wait` (16 array tasks
# and the merge job) and run again locally with --jobs 2; the merged results must be identical:
# summary.json and index.html byte for byte, runs.csv but for its two timing columns.
# Skips (exit 77) only where the daemons cannot run: not installed, or not root.
# Usage: slurm_sweep_test.sh HILRIG
set -euo pipefail
hilrig=$1

for tool in munged slurmctld slurmd sbatch sinfo; do
  command -v "$tool" >/dev/null || { echo "SKIP: $tool is not installed (scripts/setup installs slurm-wlm and munge)"; exit 77; }
done
[[ $(id -u) -eq 0 ]] || { echo "SKIP: the test cluster's daemons run as root"; exit 77; }
[[ -r /etc/munge/munge.key ]] || { echo "SKIP: no munge key (/etc/munge/munge.key)"; exit 77; }

work=$(mktemp -d)
stop_cluster() {
  for pid_file in "$work"/slurmd.pid "$work"/slurmctld.pid "$work"/munge/munged.pid; do
    [[ -f $pid_file ]] && kill "$(cat "$pid_file")" 2>/dev/null || true
  done
  sleep 0.5
  rm -rf "$work"
}
trap stop_cluster EXIT

# Ports of its own, so that a Slurm already on the machine is left alone.
base=$((20000 + RANDOM % 20000))
host=$(hostname -s)
mkdir -p "$work"/state "$work"/spool "$work"/munge
chown munge:munge "$work"/munge
cat >"$work/slurm.conf" <<CONF
ClusterName=hilrig-test
SlurmctldHost=$host
SlurmUser=root
SlurmctldPort=$base
SlurmdPort=$((base + 1))
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
# Tasks start as soon as a CPU is free, not in rounds 3 s apart (batch_sched_delay's default):
# on two CPUs the 16 array tasks otherwise take 8 rounds, 24 s for well under a second of work.
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
# `sbatch --wait` keeps polling every 2 s only while 2 s is at least half of MinJobAge (so that a
# finished job cannot be purged between two polls); at the default 300 s it sleeps 2, 8 and then
# 32 s, longer than the whole sweep takes here. At 4 s a finished job stays listed for two polls.
MinJobAge=4
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=hilrig Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
munged --socket="$work/munge/munge.sock" --pid-file="$work/munge/munged.pid" \
  --log-file="$work/munge/munged.log" --seed-file="$work/munge/seed" --force 2>/dev/null
slurmctld
slurmd
for _ in $(seq 1 100); do
  sinfo -h -o %T 2>/dev/null | grep -q idle && break
  sleep 0.1
done
sinfo -h -o %T | grep -q idle || { echo "FAIL: the test cluster did not come up"; cat "$work"/*.log; exit 1; }

# 64 cases: one second of hover over 2 masses and 32 seeds.
cat >"$work/hover.textproto" <<SPEC
name: "hover_sweep"
vehicle { initial_position_m { z: 1 } }
simulation { duration_s: 1 }
envelopes { name: "altitude" signal: ALTITUDE_ERROR_M upper: 0.05 }
SPEC
cat >"$work/sweep.textproto" <<SPEC
name: "hover_mass"
scenario: "hover.textproto"
seeds { count: 32 }
axis { path: "vehicle.mass_kg" list { value: 0.5 value: 0.6 } }
criterion { envelope: "altitude" min_pass_rate: 0.9 }
SPEC

"$hilrig" sweep "$work/sweep.textproto" --out "$work/cluster" --slurm --jobs 16 --partition hilrig \
  --wait >"$work/cluster.out" 2>"$work/cluster.err" || {
  echo "FAIL: hilrig sweep --slurm exited $?"; cat "$work/cluster.err" "$work/cluster.out"
  cat "$work"/cluster/slurm/*.out 2>/dev/null || true; exit 1; }
"$hilrig" sweep "$work/sweep.textproto" --out "$work/local" --jobs 2 >/dev/null 2>&1 || {
  echo "FAIL: the local sweep exited $?"; exit 1; }

shards=$(ls "$work"/cluster/shards/*.jsonl | wc -l)
[[ $shards -eq 16 ]] || { echo "FAIL: $shards shard files from the cluster, 16 expected"; exit 1; }
grep -q "hover_mass: 64 of 64 cases, 0 not passed" "$work/cluster.out" || {
  echo "FAIL: the cluster's sweep did not report 64 of 64"; cat "$work/cluster.out"; exit 1; }
cmp "$work/cluster/summary.json" "$work/local/summary.json" || {
  echo "FAIL: summary.json differs between the cluster and the local sweep"; exit 1; }
untimed() { sed -E 's/,[^,]*,[^,]*$//' "$1"; }
cmp <(untimed "$work/cluster/runs.csv") <(untimed "$work/local/runs.csv") || {
  echo "FAIL: runs.csv differs between the cluster and the local sweep"; exit 1; }
cmp "$work/cluster/index.html" "$work/local/index.html" || {
  echo "FAIL: index.html differs between the cluster and the local sweep"; exit 1; }
echo "PASS: 64 cases in 16 Slurm array tasks merge to the local sweep's results"
