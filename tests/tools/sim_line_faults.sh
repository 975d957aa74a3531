#!/usr/bin/env bash
# `sabus sim --line-faults` on a pseudo-terminal with line emulation, and
# `sabus run` over it with the line default (--retries 1): the status,
# device-type and read-back vectors pass or end in error, none fails; the
# run's summary gives the line figures, and the simulator's log says how
# many faults it made. Then the same line with --retries 0: the run fails
# and its failures say the reply showed a line fault.
# Usage: sim_line_faults.sh SABUS WORKDIR
set -euo pipefail
sabus="$1"
work="$2"
rm -rf "$work"
mkdir -p "$work"
run_over_noise() {  # NAME RETRIES
  local link="$work/pty-$1"
  "$sabus" sim --pty --link "$link" --emulate-line --line-faults 0.005 --line-fault-seed 7 --log "$work/sim-$1.log" \
    >"$work/sim-$1.out" 2>&1 &
  local sim=$!
  for _ in $(seq 100); do grep -q READY "$work/sim-$1.out" 2>/dev/null && break; sleep 0.1; done
  local status=0
  "$sabus" run --port "$link" --pace 0 --retries "$2" --allow-destructive \
    --filter '3.1-*' --filter '3.2-*' --filter '3.11-*' --filter 'framing-status-replies-not-garbled' >"$work/run-$1.log" 2>&1 || status=$?
  kill -INT "$sim" 2>/dev/null || true
  wait "$sim" 2>/dev/null || true
  echo "$status"
}
status=$(run_over_noise default 1)
tail -n 4 "$work/run-default.log"
if [ "$status" -ne 0 ] && [ "$status" -ne 6 ]; then echo "FAIL: exit $status over a noisy line with --retries 1"; cat "$work/run-default.log"; exit 1; fi
grep -q ' 0 failed' "$work/run-default.log" || { echo "FAIL: a vector failed over the noisy line"; exit 1; }
grep -Eq '^line: [0-9,]+ faults? in [0-9,]+ exchanges' "$work/run-default.log" || { echo "FAIL: no line figures"; exit 1; }
grep -Eq 'line faults made: requests [0-9]+ faults in [0-9]+ bytes' "$work/sim-default.log" || { echo "FAIL: the simulator's log has no fault count"; cat "$work/sim-default.log" | tail -5; exit 1; }
faults=$(grep -Eo '^line: [0-9,]+' "$work/run-default.log" | grep -Eo '[0-9,]+$' | tr -d ,)
[ "$faults" -gt 0 ] || { echo "FAIL: the line made no fault the runner saw"; exit 1; }
status=$(run_over_noise strict 0)
tail -n 4 "$work/run-strict.log"
[ "$status" -eq 1 ] || { echo "FAIL: exit $status with --retries 0, 1 expected"; exit 1; }
grep -q 'the reply showed a line fault' "$work/run-strict.log" || { echo "FAIL: no failure names the line"; exit 1; }
echo "a noisy simulator line: recovered with --retries 1, failures naming the line with --retries 0"
