#!/usr/bin/env bash
# What `sabus decode` costs on large captures (printed, not asserted): for
# each size given in MB (default 10 and 1000), a capture of random bytes and
# one of valid frames (the manual's examples with even parity in bit 7,
# repeated), each decoded to /dev/null as text, and the 10 MB ones as JSON
# too, under /usr/bin/time: wall and CPU seconds, MB/s (of the wall time)
# and peak resident memory. The decoder reads 64 KiB at a time, so memory
# should not grow with the size (target: a 10 MB random capture in at most
# 64 MB resident, at 5 MB/s or more).
# Usage: tools/decode-bench.sh [MB...]   SABUS=path/to/sabus to measure another build
set -euo pipefail
cd "$(dirname "$0")/.."
sabus=${SABUS:-build/tools/sabus}
[[ -x $sabus ]] || bash tools/build.sh release >/dev/null
if [[ ! -x /usr/bin/time ]]; then
  echo "decode-bench: /usr/bin/time is missing (apt-get install time, tools/install-deps.sh)" >&2
  exit 2
fi
sizes=("$@")
[[ ${#sizes[@]} -gt 0 ]] || sizes=(10 1000)
work=$(mktemp -d /tmp/sabus-decode-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT

# One chunk of 1 MB of each kind; a capture is that chunk repeated (the
# random one is drawn whole from /dev/urandom up to 100 MB, so a short
# capture repeats nothing).
/usr/bin/python3 - "$work/frames-1m.bin" vectors/examples/manual-examples.hex <<'PY'
import re, sys
text = re.sub(r'#.*', '', open(sys.argv[2]).read())
chars = bytes(int(h, 16) for h in re.findall(r'[0-9a-fA-F]{2}', text))
with_parity = bytes(c | (0x80 if bin(c).count('1') % 2 else 0) for c in chars)
block = with_parity * (1_000_000 // len(with_parity) + 1)
open(sys.argv[1], 'wb').write(block[:1_000_000])
PY

make_capture() {  # kind MB -> path
  local kind=$1 mb=$2 out="$work/$1-$2m.bin"
  if [[ $kind == random ]]; then
    if ((mb <= 100)); then
      head -c $((mb * 1000000)) /dev/urandom >"$out"
    else
      head -c 100000000 /dev/urandom >"$work/random-chunk.bin"
      for ((i = 0; i < mb / 100; i++)); do cat "$work/random-chunk.bin"; done >"$out"
      rm -f "$work/random-chunk.bin"
    fi
  else
    for ((i = 0; i < mb; i++)); do cat "$work/frames-1m.bin"; done >"$out"
  fi
  echo "$out"
}

# One decode under /usr/bin/time: a line of figures.
measure() {  # label MB args...
  local label=$1 mb=$2
  shift 2
  local status=0
  /usr/bin/time -f '%e %U %S %M' -o "$work/time.txt" "$sabus" decode "$@" >/dev/null 2>"$work/stderr.txt" || status=$?
  # (a first line "Command exited with non-zero status N" when decode exits 1:
  # a capture with discarded runs)
  read -r wall user sys rss_kb < <(tail -n 1 "$work/time.txt")
  awk -v l="$label" -v mb="$mb" -v w="$wall" -v u="$user" -v s="$sys" -v r="$rss_kb" -v st="$status" 'BEGIN {
    printf "%-24s %7.2f s wall %7.2f s cpu  %6.2f MB/s wall %6.2f MB/s cpu  %8.1f MB peak RSS (exit %d)\n", l, w, u + s, (w > 0 ? mb / w : 0), (u + s > 0 ? mb / (u + s) : 0), r / 1024, st }'
}

echo "sabus decode: $("$sabus" --version 2>/dev/null | head -1), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
for mb in "${sizes[@]}"; do
  for kind in random frames; do
    capture=$(make_capture "$kind" "$mb")
    measure "$kind $mb MB" "$mb" "$capture"
    ((mb > 100)) || measure "$kind $mb MB --json" "$mb" --json "$capture"
    rm -f "$capture"
  done
done
