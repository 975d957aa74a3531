#!/usr/bin/env bash
# Runner performance figures (printed, not asserted):
#  1. the whole vector suite in-process: wall time (target <= 1 s);
#  2. over a pty against `sabus sim --emulate-line` at 9600 baud, pacing off:
#     wall time / (wire time of every frame sent and received + the silence
#     windows) (target <= 1.25), and the mean silence window.
set -euo pipefail
cd "$(dirname "$0")/.."
sabus=build/tools/sabus
[[ -x $sabus ]] || bash tools/build.sh release >/dev/null

start=$(date +%s.%N)
$sabus run --sim --allow-motion --allow-destructive --json /tmp/sabus-perf-inprocess.json >/dev/null || true
end=$(date +%s.%N)
echo "in-process: whole suite in $(echo "$end - $start" | bc -l | cut -c1-6) s wall (target <= 1 s)"

link=$(mktemp -u /tmp/sabus-perf-pty.XXXXXX)
$sabus sim --pty --link "$link" --emulate-line >/tmp/sabus-perf-sim.out 2>&1 &
sim=$!
trap 'kill -INT $sim 2>/dev/null || true' EXIT
for _ in $(seq 50); do grep -q READY /tmp/sabus-perf-sim.out 2>/dev/null && break; sleep 0.1; done
start=$(date +%s.%N)
$sabus run --port "$link" --pace 0 --json /tmp/sabus-perf-pty.json >/dev/null || true
end=$(date +%s.%N)
python3 - "$start" "$end" /tmp/sabus-perf-pty.json <<'PY'
import json, sys
start, end, path = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
traffic = json.load(open(path))["traffic"]
byte_s = 10 / 9600                       # 10 bit times per character (READING-NOTES 2)
wire = (traffic["bytes_sent"] + traffic["bytes_received"]) * byte_s
silence = traffic["silence_listened_ms"] / 1000
wall = end - start
n = max(traffic["silence_windows"], 1)
print(f"pty, --emulate-line 9600 baud, pacing off: {wall:.3f} s wall (process start included), "
      f"{wire:.3f} s of wire time ({traffic['bytes_sent']} bytes out, {traffic['bytes_received']} in), "
      f"{silence:.3f} s in {traffic['silence_windows']} silence windows (mean {1000 * silence / n:.0f} ms), "
      f"measured turnaround {traffic['measured_turnaround_ms']:.1f} ms")
print(f"ratio wall / (wire + silence) = {wall / (wire + silence):.2f} (target <= 1.25)")
PY
