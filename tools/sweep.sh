#!/usr/bin/env bash
# The legal-profile sweep at scale (issues 13, 22): the whole suite against
# the reference controller on N random legal profiles (default 10,000), every
# vector passing or skipped for a capability the profile lacks. The seed is
# drawn fresh unless given, and printed; failing profiles are written, with
# their seeds, to sweep-failures/ (reproduce: sabus vectors sweep
# --profile-seed SEED). Prints the seed, the time, the failures and the
# skips by cause, and the cost: wall and CPU seconds and profiles per
# CPU-second (on a shared machine the wall time follows the load, the CPU
# time much less).
#   tools/sweep.sh [PROFILES] [SEED|fresh]      (builds sabus first if needed;
#                                                SABUS=path runs another binary)
set -euo pipefail
cd "$(dirname "$0")/.."
profiles="${1:-10000}"
seed="${2:-fresh}"
bin=${SABUS:-build/tools/sabus}
[ -x "$bin" ] || bash tools/build.sh >/dev/null
mkdir -p sweep-failures
log=$(mktemp sweep-failures/sweep-XXXXXX.log)
times=$(mktemp)
status=0
/usr/bin/time -o "$times" -f '%M %e %U %S' \
  "$bin" vectors sweep --profiles "$profiles" --seed "$seed" --out sweep-failures >"$log" || status=$?
read -r peak wall user sys <"$times"
rm -f "$times"
cpu=$(echo "$user + $sys" | bc -l)
echo "peak memory $peak KiB, $wall s wall, $cpu s CPU ($user user, $sys system), $(nproc) cores," \
     "$(echo "$profiles / $cpu" | bc -l | xargs printf '%.1f') profiles per CPU-second, load average $(cut -d' ' -f1-3 /proc/loadavg)"
# The per-profile lines are in the log; here the seed, the failures and the figures.
grep -E '^sweep seed ' "$log" || true
grep -E '^(  FAIL|  ABORTED|  profile written)' "$log" | head -n 50 || true
grep -E '^sweep: ' "$log" || true
grep -E '^sweep skips by cause' "$log" | sed 's/; /\n  /g' || true
echo "per-profile lines: $log"
exit "$status"
