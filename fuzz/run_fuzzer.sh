#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time (or a number of executions) from its seed corpora
# and prints the number of executions and the peak memory.
# usage: run_fuzzer.sh FUZZER SEED_DIR COMMITTED_SEED_DIR WORK_DIR SECONDS [RUNS]
# With RUNS > 0 it stops after that many executions (or SECONDS, whichever comes first). Any
# single allocation above 1 GiB is a failure (-malloc_limit_mb): readers must check a file's
# claims before they allocate (docs/reliability.md sec. 2). Leak checks are off: OpenImageIO and
# OpenEXR keep caches across inputs, and libFuzzer re-runs every such input looking for a leak.
# Exit status: libFuzzer's (0: no crash; a crash leaves its input in WORK_DIR/artifacts/).
set -uo pipefail
fuzzer=$1 seeds=$2 committed=$3 work=$4 seconds=$5 runs=${6:-0}
rm -rf "$work/corpus"
mkdir -p "$work/corpus" "$work/artifacts"
dirs=("$work/corpus" "$seeds")
[[ -d "$committed" ]] && dirs+=("$committed")
"$fuzzer" -max_total_time="$seconds" -runs="$([[ $runs -gt 0 ]] && echo "$runs" || echo -1)" -max_len=65536 -timeout=20 \
    -rss_limit_mb=4096 -malloc_limit_mb=1024 -detect_leaks=0 -print_final_stats=1 \
    -artifact_prefix="$work/artifacts/" "${dirs[@]}" > "$work/log.txt" 2>&1
status=$?
grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|#[0-9]+ +DONE)" "$work/log.txt"
if [[ $status != 0 ]]; then
    tail -n 60 "$work/log.txt"
    ls -l "$work/artifacts"
fi
exit $status
