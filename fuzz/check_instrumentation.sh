#!/usr/bin/env bash
# Checks that a fuzz target carries coverage counters for the code it tests
# and not for the libraries it links (fuzz/README.md, Coverage
# instrumentation): bash check_instrumentation.sh TARGET MIN MAX
set -euo pipefail
target=$1 min=$2 max=$3
counters=$("$target" -runs=0 2>&1 | sed -n 's/.*(\([0-9]*\) inline 8-bit counters).*/\1/p' | head -1)
echo "$(basename "$target"): ${counters:-no} inline 8-bit counters (expected $min-$max)"
[[ -n $counters ]] && ((counters >= min && counters <= max))
