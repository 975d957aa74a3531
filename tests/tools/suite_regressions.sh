#!/usr/bin/env bash
# gate.suite_regressions: the suite on each profile of
# tests/tools/suite-regressions against the reference controller on both
# sides of every open point of the spec: no failure (README.md there).
#   suite_regressions.sh SABUS
set -u
sabus="$1"
dir="$(dirname "$0")/suite-regressions"
status=0
for p in "$dir"/*.yaml; do
  for reading in reference other; do
    out=$("$sabus" run --sim --profile "$p" --reading "$reading" --allow-motion --allow-destructive -q 2>&1)
    rc=$?
    echo "$(basename "$p" .yaml) --reading $reading: exit $rc: $(tail -1 <<<"$out")"
    if [[ $rc != 0 ]]; then status=1; grep -E '^(FAIL|ERROR)' <<<"$out" | sed 's/^/    /'; fi
  done
done
exit $status
