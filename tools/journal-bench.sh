#!/usr/bin/env bash
# Cost of the reports (printed, not asserted):
#  1. the main job (the whole suite in-process, motion and destructive
#     vectors allowed) with --report-dir against the same run without
#     reports: median wall time of RUNS runs each, and the ratio
#     (target <= 1.3);
#  2. synthetic runs of 1,000, 5,000 and 20,000 vector results (a generated
#     suite of status polls, each reply decoded field by field) without
#     reports and with --report-dir: wall time and peak resident memory
#     (/usr/bin/time), which should grow linearly with the count, and the
#     size of what was written. (Most of the memory is the loaded suite:
#     the difference between the two runs is what the reports cost.)
# Usage: tools/journal-bench.sh [RUNS]   (default 5)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
sabus=build/tools/sabus
[[ -x $sabus ]] || bash tools/build.sh release >/dev/null
if [[ ! -x /usr/bin/time ]]; then
  echo "journal-bench: /usr/bin/time is missing (apt-get install time, tools/install-deps.sh)" >&2
  exit 2
fi
work=$(mktemp -d /tmp/sabus-journal-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT

# Seconds of wall time of one command, its output thrown away.
seconds() {
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null 2>&1 || true
  end=$(date +%s.%N)
  echo "$end - $start" | bc -l
}
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2)}'; }

main_job=("$sabus" run --sim --allow-motion --allow-destructive)
with=() without=()
for ((i = 0; i < runs; i++)); do
  without+=("$(seconds "${main_job[@]}")")
  rm -rf "$work/report"
  with+=("$(seconds "${main_job[@]}" --report-dir "$work/report")")
done
t_without=$(printf '%s\n' "${without[@]}" | median)
t_with=$(printf '%s\n' "${with[@]}" | median)
printf 'main job, median of %d runs: %.3f s without reports, %.3f s with --report-dir (%s), ratio %.2f (target <= 1.3)\n' \
  "$runs" "$t_without" "$t_with" \
  "$(ls -l "$work/report" | awk 'NR > 1 {printf "%s%s %d B", sep, $9, $5; sep = ", "}')" \
  "$(echo "$t_with / $t_without" | bc -l)"

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
  printf '  %6d  %9.2f  %9.1f  %9.2f  %10.1f  %12.1f  %7.1f MiB  %11.0f\n' "$n" "$wall0" "$(echo "$kib0 / 1024" | bc -l)" \
    "$wall" "$(echo "$kib / 1024" | bc -l)" \
    "$(echo "$(stat -c %s "$work/out-$n/run.json") / 1048576" | bc -l)" \
    "$(echo "$(stat -c %s "$work/out-$n/report.html") / 1048576" | bc -l)" \
    "$(echo "$wall * 1000000 / $n" | bc -l)"
  rm -rf "$work/out-$n" "$work/suite-$n"
done
