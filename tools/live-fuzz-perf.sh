#!/usr/bin/env bash
# Live fuzzer line use (printed, not asserted): `sabus fuzz` over a pty
# against `sabus sim --emulate-line` at the profile's 9600 baud, pacing off.
# Line busy % = wire time of every byte sent and received (10 bit times a
# character, READING-NOTES 2) / wall time of the run. Target: >= 80 %.
set -euo pipefail
cd "$(dirname "$0")/.."
sabus=build/tools/sabus
[[ -x $sabus ]] || bash tools/build.sh release >/dev/null
seconds=${1:-20}

link=$(mktemp -u /tmp/sabus-fuzz-perf-pty.XXXXXX)
findings=$(mktemp -d /tmp/sabus-fuzz-perf-findings.XXXXXX)
$sabus sim --pty --link "$link" --emulate-line >/tmp/sabus-fuzz-perf-sim.out 2>&1 &
sim=$!
trap 'kill -INT $sim 2>/dev/null || true; rm -rf "$findings"' EXIT
for _ in $(seq 50); do grep -q READY /tmp/sabus-fuzz-perf-sim.out 2>/dev/null && break; sleep 0.1; done
out=$($sabus fuzz --port "$link" --pace 0 --max-time "$seconds" --seed 1 --findings "$findings" || true)
echo "$out" | grep -E '^(replies|traffic|[0-9]+ writes|[0-9]+ finding)' || true
python3 - "$out" <<'PY'
import re, sys
m = re.search(r"traffic: bytes_sent=(\d+) bytes_received=(\d+) wall_s=([0-9.]+) baud=(\d+)", sys.argv[1])
if not m:
    sys.exit("no traffic line in the output of sabus fuzz")
sent, received, wall, baud = int(m[1]), int(m[2]), float(m[3]), int(m[4])
wire = (sent + received) * 10 / baud
print(f"pty, --emulate-line {baud} baud, pacing off: {wall:.3f} s of fuzzing, {wire:.3f} s of wire time "
      f"({sent} bytes out, {received} in)")
print(f"line busy = {100 * wire / wall:.1f} % (target >= 80 %)")
PY
