#!/usr/bin/env bash
# Cost of the reports (printed, not asserted):
#  1. the main job (the whole suite in-process, motion and destructive
#     vectors allowed) with --report-dir against the same run without
#     reports: median wall and CPU time of RUNS runs each (alternating),
#     and the ratios (target: wall <= 1.3); with valgrind installed, also the
#     instructions each executes;
#  2. synthetic runs of 1,000, 5,000 and 20,000 vector results (a generated
#     suite of status polls, each reply decoded field by field) without
#     reports and with --report-dir: wall time and peak resident memory
#     (/usr/bin/time), which should grow linearly with the count, and the
#     size of what was written. (Most of the memory is the loaded suite:
#     the difference between the two runs is what the reports cost.)
# Usage: tools/journal-bench.sh [RUNS]   (default 9)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-9}
sabus=build/tools/sabus
[[ -x $sabus ]] || bash tools/build.sh release >/dev/null
if [[ ! -x /usr/bin/time ]]; then
  echo "journal-bench: /usr/bin/time is missing (apt-get install time, tools/install-deps.sh)" >&2
  exit 2
fi
work=$(mktemp -d /tmp/sabus-journal-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT

# "wall cpu" seconds of one command (bash's time: milliseconds; cpu is user
# plus system), its output thrown away.
seconds() {
  local TIMEFORMAT='%3R %3U %3S' t
  t=$({ time "$@" >/dev/null 2>&1; } 2>&1) || true
  awk '{printf "%.3f %.3f\n", $1, $2 + $3}' <<<"$t"
}
# The median of column COLUMN of the lines on standard input.
median() { awk -v c="$1" '{print $c}' | sort -g | awk '{a[NR] = $1} END {print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2)}'; }

# Runs with and without reports alternate, so that a change in the machine's
# load moves both; wall time is the target's measure, CPU time (the same work
# without the other jobs' share of the machine, and without waiting for the
# disk) is printed beside it.
main_job=("$sabus" run --sim --allow-motion --allow-destructive)
with=() without=()
for ((i = 0; i < runs; i++)); do
  without+=("$(seconds "${main_job[@]}")")
  rm -rf "$work/report"
  with+=("$(seconds "${main_job[@]}" --report-dir "$work/report")")
done
for column in 1 2; do
  a=$(printf '%s\n' "${without[@]}" | median "$column")
  b=$(printf '%s\n' "${with[@]}" | median "$column")
  printf 'main job, median of %d runs, %s: %.3f s without reports, %.3f s with --report-dir, ratio %.2f%s\n' \
    "$runs" "$( ((column == 1)) && echo wall || echo CPU)" "$a" "$b" "$(awk -v a="$a" -v b="$b" 'BEGIN{print b / a}')" \
    "$( ((column == 1)) && echo " (target <= 1.3)")"
done
# Each run with reports against the run without them just before it: a
# change in the machine's speed between rounds moves one pair, not the median.
ratios=$(printf '%s\n' "${without[@]}" | paste -d' ' - <(printf '%s\n' "${with[@]}") | awk '{print $3 / $1}' | sort -g)
printf "main job, wall, the median of the %d pairs' ratios: %.2f (lowest %.2f, highest %.2f)\n" \
  "$runs" "$(median 1 <<<"$ratios")" "$(head -1 <<<"$ratios")" "$(tail -1 <<<"$ratios")"
echo "  reports: $(ls -l "$work/report" | awk 'NR > 1 {printf "%s%s %d B", sep, $9, $5; sep = ", "}')"
# Instructions executed (valgrind's callgrind, where valgrind is installed):
# the same count for the same binary and inputs whatever else the machine
# does, so the ratio of the work itself, without the noise of a shared host.
if command -v valgrind >/dev/null; then
  instructions() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | sed -n 's/.*Collected : *//p'
  }
  rm -rf "$work/report"
  i0=$(instructions "${main_job[@]}")
  i1=$(instructions "${main_job[@]}" --report-dir "$work/report")
  awk -v a="$i0" -v b="$i1" 'BEGIN {printf "main job, instructions (callgrind): %.0f M without reports, %.0f M with --report-dir, ratio %.2f\n", a / 1e6, b / 1e6, b / a}'
fi

# A suite of N status polls (§3.2): every result has a transcript with a
# 52-byte reply decoded field by field, as the heaviest common vector. The
# loader takes at most 500 vectors a group and 1 MiB a file: files of 1,000
# vectors in two groups, in one folder.
make_suite() {
  local n=$1 dir=$2 k
  mkdir -p "$dir"
  for ((k = 0; k < n; k++)); do
    if ((k % 1000 == 0)); then
      exec 3>"$dir/bench-$((k / 1000)).yaml"
      printf 'paragraph: "3.2"\ntitle: synthetic status polls for tools/journal-bench.sh\ngroups:\n' >&3
    fi
    ((k % 500 == 0)) && printf '  - comment: One status poll each.\n    level: must\n    vectors:\n' >&3
    printf '      - id: 3.2-bench-status-%05d\n        comment: A status poll answered by an ACK and 52 bytes.\n' "$k" >&3
    printf '        spec: {paragraph: "3.2", quote: "The response to this command will consist of 52 bytes"}\n' >&3
    printf '        steps:\n          - send: {command: status}\n' >&3
    printf '            expect: {reply: ack, fields: {command: 0x31, ETX: 0x03}}\n' >&3
  done
  exec 3>&-
}

# Wall seconds and peak KiB of one run, "wall kib" into FILE; exits on failure.
measure() {
  local file=$1
  shift
  if ! /usr/bin/time -f '%e %M' -o "$file" "$@" >"$file.console" 2>&1; then
    echo "journal-bench: $* failed:" >&2
    tail -n 5 "$file.console" >&2
    exit 1
  fi
}

echo "synthetic runs (--sim, N status polls): wall time and peak memory without reports (plain) and with --report-dir (report):"
printf '  %6s  %9s  %9s  %9s  %10s  %12s  %11s  %11s\n' N "plain s" "plain MiB" "report s" "report MiB" "run.json MiB" "report.html" "µs/vector"
for n in 1000 5000 20000; do
  make_suite "$n" "$work/suite-$n"
  rm -rf "$work/out-$n"
  measure "$work/plain-$n" "$sabus" run --sim --vectors "$work/suite-$n"
  measure "$work/time-$n" "$sabus" run --sim --vectors "$work/suite-$n" --report-dir "$work/out-$n"
  read -r wall0 kib0 <"$work/plain-$n"
  read -r wall kib <"$work/time-$n"
  awk -v n="$n" -v w0="$wall0" -v k0="$kib0" -v w="$wall" -v k="$kib" -v j="$(stat -c %s "$work/out-$n/run.json")" \
    -v h="$(stat -c %s "$work/out-$n/report.html")" \
    'BEGIN {printf "  %6d  %9.2f  %9.1f  %9.2f  %10.1f  %12.1f  %7.1f MiB  %11.0f\n", n, w0, k0 / 1024, w, k / 1024, j / 1048576, h / 1048576, w * 1000000 / n}'
  rm -rf "$work/out-$n" "$work/suite-$n"
done
