#!/usr/bin/env bash
# Runs one golden test of the command line, in the way OpenImageIO keeps testsuite/*/ref/: the
# case's run.sh runs npf commands in a fresh folder, each through `run`, which writes the command,
# its stdout, its stderr and its exit status to out.txt; out.txt must equal ref/out.txt byte for
# byte. Paths in the output are relative to the folder, so the text is the same on any machine.
#
# usage: runtest.sh CASE_DIR NPF [SOURCE_DIR]
#   NPF_TESTSUITE_UPDATE=1 writes ref/out.txt instead of comparing (review the diff before you
#   commit it: a changed reference is a changed behaviour).
set -uo pipefail
case_dir=$(cd "$1" && pwd) npf=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
src=${3:-$(cd "$(dirname "$0")/.." && pwd)}
work=$(mktemp -d "${TMPDIR:-/tmp}/npf-testsuite.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1

# run ARGS...: one npf command (the first word "npf" is the tool under test).
run() {
    local out err status
    [[ $1 == npf ]] && shift && set -- "$npf" "$@"
    out=$(mktemp) err=$(mktemp)
    "$@" > "$out" 2> "$err"
    status=$?
    {
        printf '$ %s\n' "$(printf '%s ' "$@" | sed "s|$npf|npf|g; s/ $//")"
        cat "$out"
        if [[ -s $err ]]; then printf -- '--- stderr\n'; cat "$err"; fi
        printf -- '--- exit %d\n\n' "$status"
    } >> out.txt
    rm -f "$out" "$err"
}
# note TEXT: a line of its own in out.txt (what a group of commands shows).
note() { printf '# %s\n' "$*" >> out.txt; }
# same A B: whether two outputs are byte-identical, as a line in out.txt.
same() {
    if cmp -s "$1" "$2"; then note "$1 and $2 are byte-identical"; else note "$1 and $2 DIFFER"; fi
}
export -f run note same
export npf src

: > out.txt
# Each case sees NPF (the tool) and SRC (the source tree, for shipped recipes and configs).
NPF=$npf SRC=$src bash -c "source '$case_dir/run.sh'" >> run.log 2>&1
status=$?
if [[ $status != 0 ]]; then
    echo "testsuite $(basename "$case_dir"): run.sh failed (exit $status):"
    cat run.log
    exit 1
fi

# What changes from run to run is not compared: the folder's name, durations and peak memory.
sed -E -i -e "s|$work|.|g" \
    -e 's/^(  time +).*/\1(not compared)/' \
    -e 's/\b[0-9]+(\.[0-9]+)? s\b/# s/g' \
    -e 's/peak memory [0-9.]+ [KMG]iB/peak memory # GiB/g' out.txt

if [[ ${NPF_TESTSUITE_UPDATE:-0} == 1 ]]; then
    mkdir -p "$case_dir/ref"
    cp out.txt "$case_dir/ref/out.txt"
    echo "testsuite $(basename "$case_dir"): ref/out.txt written"
    exit 0
fi
if ! diff -u "$case_dir/ref/out.txt" out.txt; then
    echo "testsuite $(basename "$case_dir"): the output differs from ref/out.txt (above)"
    exit 1
fi
echo "testsuite $(basename "$case_dir"): matches ref/out.txt"
