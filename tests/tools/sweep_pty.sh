#!/usr/bin/env bash
# Five profiles of the legal-profile sweep through `sabus sim` on a
# pseudo-terminal with line emulation (turnaround, wire time), each run by
# `sabus run` over the pty: the status, device-type, extended-status and
# read-back vectors and the offline ones (a profile may disable remote
# control) must pass or be skipped for a capability, as they do
# in-process. Usage: sweep_pty.sh SABUS WORKDIR
set -euo pipefail
sabus="$1"
work="$2"
rm -rf "$work"
mkdir -p "$work/profiles"
"$sabus" vectors sweep --profiles 5 --seed 11 --write-profiles "$work/profiles" --out "$work/failures" >"$work/sweep.log"
n=0
for profile in "$work"/profiles/sweep-*.yaml; do
  n=$((n + 1))
  link="$work/pty-$n"
  "$sabus" sim --pty --link "$link" --profile "$profile" --emulate-line >"$work/sim-$n.log" 2>&1 &
  sim=$!
  for _ in $(seq 100); do grep -q READY "$work/sim-$n.log" 2>/dev/null && break; sleep 0.1; done
  status=0
  "$sabus" run --port "$link" --profile "$profile" --pace 0 --allow-destructive \
    --filter '3.1-*' --filter '3.2-*' --filter '3.11-*' --filter '3.17-*' --filter 'offline-*' >"$work/run-$n.log" 2>&1 || status=$?
  kill "$sim" 2>/dev/null || true
  wait "$sim" 2>/dev/null || true
  echo "$(basename "$profile"): $(tail -n 1 "$work/run-$n.log")"
  if [ "$status" -ne 0 ] || ! grep -q ' passed, 0 failed' "$work/run-$n.log"; then
    echo "FAIL: $profile over a pty (exit $status)"; cat "$work/run-$n.log"; exit 1
  fi
done
[ "$n" -eq 5 ] || { echo "FAIL: $n profiles written, 5 expected"; exit 1; }
echo "5 swept profiles passed over a pty with line emulation"
