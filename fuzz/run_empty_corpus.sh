#!/usr/bin/env bash
# Runs one libFuzzer target for a few seconds from an empty corpus, as
# OSS-Fuzz's bad-build check and a ClusterFuzzLite job without a stored
# corpus do, with the flags of its .options file (no dictionary, no seeds).
# libFuzzer then runs one input ("\n") first and stops with "no interesting
# inputs were found" when that input reaches no instrumented code, so this
# fails on that, on any crash, leak, sanitizer report, timeout or oracle
# failure, and when libFuzzer reports no coverage at all.
#   run_empty_corpus.sh TARGET [OPTIONS_FILE]      (EMPTY_CORPUS_SECONDS, default 5)
set -uo pipefail
target=$1 options=${2:-}
seconds=${EMPTY_CORPUS_SECONDS:-5}
name=$(basename "$target")
work=$(mktemp -d "${TMPDIR:-/tmp}/sabus-empty-$name.XXXXXX")
mkdir -p "$work/corpus" "$work/artifacts"
flags=()
# [libfuzzer] key = value lines of the .options file (the OSS-Fuzz format).
if [[ -n $options && -f $options ]]; then
  while IFS= read -r line; do
    [[ $line =~ ^[[:space:]]*([a-z_]+)[[:space:]]*=[[:space:]]*(.*[^[:space:]])[[:space:]]*$ ]] || continue
    key=${BASH_REMATCH[1]} value=${BASH_REMATCH[2]}
    [[ $key == dict ]] && continue  # started from nothing: no dictionary either
    flags+=("-$key=$value")
  done <"$options"
fi
"$target" "${flags[@]}" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$work/artifacts/" "$work/corpus" >"$work/log" 2>&1
status=$?
inited=$(grep -m1 -E '^#[0-9]+[[:space:]]+INITED' "$work/log")
inputs=$(find "$work/corpus" -type f | wc -l)
runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/log")
problem=""
if grep -q 'no interesting inputs were found' "$work/log"; then
  problem="libFuzzer found no interesting input: the first input reached no instrumented code"
elif ((status != 0)); then
  problem="libFuzzer exited with status $status"
elif ! [[ $inited =~ cov:\ [1-9] ]]; then
  problem="no coverage reported at INITED: ${inited:-no INITED line}"
fi
if [[ -n $problem ]]; then
  tail -40 "$work/log"
  echo "EMPTY-CORPUS FAILURE in $name: $problem"
  ls "$work/artifacts" | sed "s|^|  reproducer: $work/artifacts/|"
  exit 1
fi
echo "ok: $name from an empty corpus: ${runs:-?} runs in ${seconds} s, $inputs inputs in its corpus; ${inited}"
rm -rf "$work"
