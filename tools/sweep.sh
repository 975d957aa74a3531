#!/usr/bin/env bash
# The legal-profile sweep at scale (issue 13): the whole suite against the
# reference controller on N random legal profiles (default 1,000), every
# vector passing or skipped for a capability the profile lacks. Failing
# profiles are written, with their seeds, to sweep-failures/.
#   tools/sweep.sh [PROFILES] [SEED]      (builds sabus first if needed)
set -euo pipefail
cd "$(dirname "$0")/.."
profiles="${1:-1000}"
seed="${2:-1}"
bin=build/tools/sabus
[ -x "$bin" ] || bash tools/build.sh >/dev/null
log=sweep-failures/sweep-$seed-$profiles.log
mkdir -p sweep-failures
status=0
/usr/bin/time -f 'peak memory %M KiB, %e s wall' \
  "$bin" vectors sweep --profiles "$profiles" --seed "$seed" --out sweep-failures >"$log" || status=$?
# The per-profile lines are in the log; here the failures and the figures.
grep -E '^(  FAIL|  ABORTED|  profile written)' "$log" | head -n 50 || true
tail -n 1 "$log"
echo "per-profile lines: $log"
exit "$status"
