#!/usr/bin/env bash
# Runs one libFuzzer target for FUZZ_SECONDS (default 30) from its seed corpus
# and its regression seeds, with the flags of its .options file and its
# dictionary. Fails on any crash, leak, sanitizer report, timeout, memory
# limit or oracle failure (an abort), and prints the reproducer path.
#   run_fuzzer.sh TARGET SEED_DIR REGRESSION_DIR [OPTIONS_FILE [DICT]]
set -uo pipefail
target=$1 seeds=$2 regressions=$3 options=${4:-} dict=${5:-}
seconds=${FUZZ_SECONDS:-30}
name=$(basename "$target")
work=$(mktemp -d "${TMPDIR:-/tmp}/sabus-fuzz-$name.XXXXXX")
artifacts=${FUZZ_ARTIFACTS:-$PWD/fuzz-artifacts/$name}
mkdir -p "$artifacts" "$regressions"
cp -r "$seeds"/. "$work"/ 2>/dev/null || true
flags=()
# [libfuzzer] key = value lines of the .options file (the OSS-Fuzz format).
if [[ -n $options && -f $options ]]; then
  while IFS= read -r line; do
    [[ $line =~ ^[[:space:]]*([a-z_]+)[[:space:]]*=[[:space:]]*(.*[^[:space:]])[[:space:]]*$ ]] || continue
    key=${BASH_REMATCH[1]} value=${BASH_REMATCH[2]}
    [[ $key == dict ]] && continue  # the dictionary is passed by path below
    flags+=("-$key=$value")
  done <"$options"
fi
if [[ -n $dict && -f $dict ]]; then flags+=("-dict=$dict"); fi
before=$(ls -1 "$artifacts" 2>/dev/null)
"$target" "${flags[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$artifacts/" "$work" "$regressions" >"$work.log" 2>&1
status=$?
grep -E "^(stat::number_of_executed_units|stat::average_exec_per_sec|stat::peak_rss_mb|#[0-9]+ +DONE)" "$work.log" | head -5
if [ $status -ne 0 ]; then
  tail -40 "$work.log"
  echo "FUZZ FAILURE in $name (exit $status): reproducer(s):"
  comm -13 <(echo "$before") <(ls -1 "$artifacts") | sed "s|^|  $artifacts/|"
  echo "  replay: $target <reproducer>; keep it as a regression seed in fuzz/regressions/$name/"
fi
rm -rf "$work" "$work.log"
exit $status
