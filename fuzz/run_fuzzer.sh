#!/usr/bin/env bash
# Runs one libFuzzer target for FUZZ_SECONDS (default 10) from its seed corpus
# and its regression seeds. Fails on any crash, leak, sanitizer report or
# oracle failure, and prints the reproducer path.
#   run_fuzzer.sh TARGET SEED_DIR REGRESSION_DIR
set -uo pipefail
target=$1 seeds=$2 regressions=$3
seconds=${FUZZ_SECONDS:-10}
name=$(basename "$target")
work=$(mktemp -d "${TMPDIR:-/tmp}/sabus-fuzz-$name.XXXXXX")
artifacts=${FUZZ_ARTIFACTS:-$PWD/fuzz-artifacts/$name}
mkdir -p "$artifacts" "$regressions"
cp -r "$seeds"/. "$work"/ 2>/dev/null || true
before=$(ls -1 "$artifacts" 2>/dev/null)
"$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$artifacts/" "$work" "$regressions" >"$work.log" 2>&1
status=$?
grep -E "^(stat::|#[0-9]+ +DONE)" "$work.log" | head -5
if [ $status -ne 0 ]; then
  tail -40 "$work.log"
  echo "FUZZ FAILURE in $name: reproducer(s):"
  comm -13 <(echo "$before") <(ls -1 "$artifacts") | sed "s|^|  $artifacts/|"
  echo "  replay: $target <reproducer>; keep it as a regression seed in fuzz/regressions/$name/"
fi
rm -rf "$work" "$work.log"
exit $status
