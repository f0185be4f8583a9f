#!/usr/bin/env bash
# Opt-in test (ctest label "slurm", -DNPF_SLURM_TEST=ON): runs configs/batch/slurm-array.sh on a
# single-node Slurm cluster started here on loopback (slurmctld + slurmd, no munge: auth/none),
# and checks that the shards' outputs equal those of one `npf batch` process byte for byte and
# that the merge job wrote a summary of every material.
#
# usage: run_slurm_loopback.sh NPF_EXECUTABLE SOURCE_DIR [SHARDS]
# Exit status: 0 passed, 1 failed, 77 skipped (slurm-wlm not installed, or the daemons would not
# start here). Needs to run as root or as a user who may start slurmd.
set -uo pipefail

npf=$(realpath "$1")
src=$(realpath "$2")
shards=${3:-3}
for tool in slurmctld slurmd sbatch sinfo squeue scontrol; do
    command -v "$tool" > /dev/null || { echo "SKIP: $tool not found (apt-get install slurm-wlm)"; exit 77; }
done

work=$(mktemp -d "${TMPDIR:-/tmp}/npf-slurm-XXXXXX")
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2> /dev/null; done
    for pid in "${pids[@]}"; do wait "$pid" 2> /dev/null; done
    [[ -n "${NPF_KEEP_TEST_FILES:-}" ]] && echo "kept $work" || rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; for f in "$work"/log/*.log "$work"/summaries/slurm-*.out; do [[ -f $f ]] && { echo "--- $f"; tail -n 20 "$f"; }; done; exit 1; }

# Free ports on loopback for the two daemons.
port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
ctld_port=$(port)
slurmd_port=$(port)
host=$(hostname -s)
cpus=$(nproc)
user=$(id -un)
mkdir -p "$work"/{state,spool,log,summaries}
cat > "$work/slurm.conf" << CONF
ClusterName=npftest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=root
AuthType=auth/none
CredType=cred/none
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
SwitchType=switch/none
NodeName=npfnode NodeHostname=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=1000 State=UNKNOWN
PartitionName=npf Nodes=npfnode Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf

slurmctld -D -i -f "$SLURM_CONF" > "$work/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N npfnode -f "$SLURM_CONF" > "$work/log/slurmd.out" 2>&1 &
pids+=($!)
ready=0
for _ in $(seq 1 60); do
    state=$(sinfo -h -n npfnode -o '%T' 2> /dev/null)
    [[ "$state" == idle* ]] && { ready=1; break; }
    sleep 0.5
done
if [[ $ready != 1 ]]; then
    echo "SKIP: the loopback Slurm cluster did not come up (state '${state:-none}')"
    tail -n 5 "$work/log/slurmctld.log" "$work/log/slurmd.log" 2> /dev/null
    exit 77
fi
echo "slurm: $(sinfo -V) node npfnode idle, ${cpus} CPUs"

# A small library: the shipped RGL file and the analytic recipes, at a tiny grid.
write_config() {
    cat > "$1" << YAML
output_dir: $2
inputs:
  - $src/data/materials/*.bsdf
  - $src/configs/materials/*.yaml
defaults:
  preset: preview
  threads: 1
  grid: [16, 16, 16, 32]
  g_grid: [16, 16]
  max_wavelengths: 4
  error_pairs: 1000
YAML
}
write_config "$work/one.yaml" "$work/one"
write_config "$work/shards.yaml" "$work/shards"

ms() { echo $(($(date +%s%N) / 1000000)); }
start=$(ms)
"$npf" batch "$work/one.yaml" --quiet > "$work/log/one.log" 2>&1 || fail "single-process batch failed"
t_one=$(($(ms) - start))

start=$(ms)
NPF="$npf" SUMMARY_DIR="$work/summaries" NPF_SLURM_WAIT=1 \
    timeout 300 bash "$src/configs/batch/slurm-array.sh" "$work/shards.yaml" "$shards" > "$work/log/submit.log" 2>&1
status=$?
t_slurm=$(($(ms) - start))
cat "$work/log/submit.log"
[[ $status == 0 ]] || fail "slurm-array.sh (merge job) exited $status"

n_one=$(ls "$work/one"/*.exr | wc -l)
[[ $n_one -gt 0 ]] || fail "no outputs from the single process"
for f in "$work/one"/*.exr; do
    cmp -s "$f" "$work/shards/$(basename "$f")" || fail "$(basename "$f"): Slurm shards and one process differ"
done
n_shards=$(ls "$work/shards"/*.exr | wc -l)
[[ $n_shards == "$n_one" ]] || fail "$n_shards outputs from Slurm, $n_one from one process"
[[ -f "$work/summaries/batch-summary.json" ]] || fail "no merged summary"
grep -q '"ok": true' "$work/summaries/batch-summary.json" || fail "merged summary is not ok"
grep -q "\"shards\": \[$(seq -s ', ' 0 $((shards - 1)))\]" "$work/summaries/batch-summary.json" || fail "merged summary lacks a shard"
for k in $(seq 0 $((shards - 1))); do [[ -f "$work/summaries/shard-$k-of-$shards.json" ]] || fail "no summary of shard $k"; done
echo "PASS: $shards Slurm array tasks + merge job wrote the $n_one outputs of one process byte for byte" \
     "(one process ${t_one} ms, Slurm submit to merged ${t_slurm} ms)"
exit 0
