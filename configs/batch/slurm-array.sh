#!/usr/bin/env bash
# Runs an npf batch as a Slurm job array: one array task per shard, each
#   npf batch CONFIG --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT
# and then one job, started when every task has ended (afterany: failed materials make a task
# exit non-zero, and the merge still runs), that merges the shards' summaries into one.
#
# usage: configs/batch/slurm-array.sh CONFIG.yaml SHARDS [sbatch options...]
#   NPF=/path/to/npf          the npf executable the nodes run (default: npf on PATH)
#   SUMMARY_DIR=DIR           where the shard summaries, the merged summary and the Slurm logs go
#                             (default: ./npf-batch-summaries; must be on a shared file system)
#   NPF_SLURM_WAIT=1          wait for the merge job and exit with its status (sbatch --wait)
# Example: NPF=$PWD/build/tools/npf/npf configs/batch/slurm-array.sh configs/batch/example.yaml 4 --partition=cpu
#
# Every task writes only its own materials' outputs (material i of the name-sorted list goes to
# shard i mod N); the outputs are those a single `npf batch CONFIG` writes, byte for byte, when
# the configuration fixes `threads` (docs/batch.md). Re-submitting skips what is done.
set -euo pipefail

if [[ $# -lt 2 ]]; then
    sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
config=$(realpath "$1")
shards=$2
shift 2
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || { echo "slurm-array.sh: SHARDS must be a positive whole number, got '$shards'" >&2; exit 2; }
npf=${NPF:-$(command -v npf || true)}
[[ -n "$npf" && -x "$npf" ]] || { echo "slurm-array.sh: set NPF to the npf executable" >&2; exit 2; }
npf=$(realpath "$npf")
summary_dir=$(realpath -m "${SUMMARY_DIR:-$PWD/npf-batch-summaries}")
mkdir -p "$summary_dir"

# Check the configuration here, before anything is queued.
"$npf" batch "$config" --check > /dev/null

q() { printf '%q' "$1"; }
task="exec $(q "$npf") batch $(q "$config") --quiet"
task+=" --shard \$SLURM_ARRAY_TASK_ID/\$SLURM_ARRAY_TASK_COUNT"
task+=" --summary $(q "$summary_dir")/shard-\$SLURM_ARRAY_TASK_ID-of-\$SLURM_ARRAY_TASK_COUNT"
array_job=$(sbatch --parsable --job-name=npf-batch --array="0-$((shards - 1))" \
    --output="$summary_dir/slurm-%A_%a.out" "$@" --wrap="$task")
array_job=${array_job%%;*}

merge="exec $(q "$npf") batch --merge"
for ((k = 0; k < shards; ++k)); do merge+=" $(q "$summary_dir/shard-$k-of-$shards.json")"; done
merge+=" -o $(q "$summary_dir/batch-summary")"
wait_flag=()
[[ "${NPF_SLURM_WAIT:-0}" == 1 ]] && wait_flag=(--wait)
echo "npf batch: array job $array_job ($shards shards); summaries in $summary_dir"
merge_job=$(sbatch --parsable "${wait_flag[@]}" --job-name=npf-batch-merge --dependency="afterany:$array_job" \
    --output="$summary_dir/slurm-merge-%j.out" "$@" --wrap="$merge") && status=0 || status=$?
echo "npf batch: merge job ${merge_job%%;*} -> $summary_dir/batch-summary.json, .md"
exit $status
