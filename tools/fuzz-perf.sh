#!/usr/bin/env bash
# Prints the fuzz targets' speed on one core and what the whole-controller
# target reaches in a given time (figures are printed, never asserted):
#   tools/fuzz-perf.sh [SECONDS]     (SECONDS=0: only step 1)
# 1. every target runs EXEC_SECONDS (default 20; 0 skips this) from its seed corpus, pinned
#    to one core (taskset -c 0): libFuzzer's exec/s, and executions per
#    CPU-second of the process (the same figure on a machine shared with
#    other jobs, where wall-clock exec/s understates the target); then the
#    floors, and each frame-level target's executions per CPU-second as a
#    share of its floor's, measured in this run (goals: fuzz_receiver 0.7,
#    fuzz_controller 0.6), from the table and again in ROUNDS rounds of
#    PAIR_SECONDS in which target and floor run one after the other (paired);
# 2. fuzz_controller runs SECONDS (default 300) from its seed corpus on one
#    core: its final edge coverage, then fuzz_handler_report replays the
#    resulting corpus (each input cut to max_len, as libFuzzer runs it) and
#    lists the command handlers (and forms, and NAK rules) the corpus reaches;
# 3. time to full coverage: while step 2 runs, and in a second run from an
#    empty corpus (EMPTY_SECONDS, default SECONDS; 0 skips it), every POLL
#    seconds (default 2) `fuzz_handler_report --missing` reads the corpus on
#    the other core; the first time it finds every command ACKed and every NAK
#    rule fired, the fuzzer's CPU seconds so far are the time to all handlers
#    and NAK rules (an upper bound: the corpus had them by then at the latest).
# Step 1 also runs the floors (fuzz/perf_floor.cpp): libFuzzer with a target
# that does nothing, the receiver fed once, and the controller executing
# frames, all without an oracle -- what the targets' speeds compare with.
# BUILD (default build-fuzz-perf): the build tree of the targets. Made here
# when missing: libFuzzer without sanitizers (-fsanitize=fuzzer through
# SABUS_FUZZ_ENGINE), the engine's own speed. BUILD=build-fuzz measures the
# ASan+UBSan flavour the tests run (tools/build.sh fuzz).
# The corpora and logs go to a directory on tmpfs (/dev/shm, or
# FUZZ_PERF_TMP): libFuzzer writes a file for every new or reduced input, and
# on a shared disk that cost varied from run to run by more than the oracles
# (ext4 inode allocation under other jobs' writes).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-300}
exec_seconds=${EXEC_SECONDS:-20}
empty_seconds=${EMPTY_SECONDS:-$seconds}
poll=${POLL:-2}
build=${BUILD:-build-fuzz-perf}
if [[ ! -f $build/build.ninja ]]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
    -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" -DSABUS_FUZZ_ENGINE=-fsanitize=fuzzer \
    -DSABUS_BUILD_TESTS=OFF -DSABUS_BUILD_BENCHMARKS=OFF -DSABUS_BUILD_TOOLS=OFF >/dev/null
fi
cmake --build "$build" --target all_fuzzers fuzz_handler_report fuzz_seeds fuzz_floors >/dev/null
fuzz=$build/fuzz
tmp=${FUZZ_PERF_TMP:-}
if [[ -z $tmp ]]; then
  if [[ -d /dev/shm && -w /dev/shm ]]; then tmp=/dev/shm; else tmp=${TMPDIR:-/tmp}; fi
fi
work=$(mktemp -d "$tmp/sabus-fuzz-perf.XXXXXX")
trap 'rm -rf "$work"' EXIT

# libFuzzer flags of a target's .options file (the dictionary by path).
flags_of() {
  local t=$1 line key value
  while IFS= read -r line; do
    [[ $line =~ ^[[:space:]]*([a-z_]+)[[:space:]]*=[[:space:]]*(.*[^[:space:]])[[:space:]]*$ ]] || continue
    key=${BASH_REMATCH[1]} value=${BASH_REMATCH[2]}
    if [[ $key == dict ]]; then echo "-dict=$fuzz/seeds/$value"; else echo "-$key=$value"; fi
  done <"$fuzz/$t.options"
}

# fuzz_on_core LABEL BINARY SECONDS SEEDS FLAGS...: starts BINARY in the
# background for SECONDS on core 0 from a copy of SEEDS (none: an empty
# corpus; left in $work/LABEL) with FLAGS; its output goes to $work/LABEL.log,
# its user and system CPU time to $work/LABEL.time. Sets `timer` to the pid
# of /usr/bin/time, whose child is the fuzzer.
fuzz_on_core() {
  local label=$1 binary=$2 limit=$3 seeds=$4
  shift 4
  mkdir -p "$work/$label"
  [[ -z $seeds ]] || cp "$seeds"/* "$work/$label/"
  /usr/bin/time -f "%U %S" -o "$work/$label.time" taskset -c 0 "$binary" "$@" -max_total_time="$limit" \
    -print_final_stats=1 -artifact_prefix="$work/" "$work/$label" >"$work/$label.log" 2>&1 &
  timer=$!
}

# finished LABEL STATUS [STOPPED]: fails the script on a fuzzer that failed
# (a finding, a crash), unless it was stopped here (libFuzzer exits 72 on SIGINT).
finished() {
  local label=$1 status=$2 stopped=${3:-}
  [[ $status == 0 || ($stopped == yes && $status == 72) ]] && return
  echo "$label failed:"; tail -30 "$work/$label.log"; exit 1
}

cpu_seconds() { awk '{printf "%.1f", $1 + $2}' "$work/$1.time"; }

# measure LABEL BINARY SECONDS SEEDS FLAGS...: runs BINARY as fuzz_on_core
# does; sets rate (libFuzzer's exec/s), runs, cpu and per_cpu[LABEL]
# (executions per CPU-second).
declare -A per_cpu
measure() {
  local label=$1 binary=$2 limit=$3 seeds=$4 status=0
  shift 4
  fuzz_on_core "$label" "$binary" "$limit" "$seeds" "$@"
  wait "$timer" || status=$?
  finished "$label" "$status"
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$work/$label.log")
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/$label.log")
  cpu=$(cpu_seconds "$label")
  per_cpu[$label]=$(awk -v r="$runs" -v c="$cpu" 'BEGIN{printf "%d", (c > 0) ? r / c : 0}')
}

# row LABEL BINARY SEEDS FLAGS...: one row of the table, EXEC_SECONDS of BINARY.
row() {
  local label=$1 binary=$2 seeds=$3
  shift 3
  measure "$label" "$binary" "$exec_seconds" "$seeds" "$@"
  printf "%-26s %12s %14s %10s %16s\n" "$label" "$rate" "$runs" "$cpu" "${per_cpu[$label]}"
}

# paired TARGET: the target's share of its floor again, in ROUNDS (default 5)
# rounds of PAIR_SECONDS (default 10) each, the target and then its floor in
# every round, each from its seed corpus: a change in the machine's load
# between two rows of the table (other jobs on a shared host moved a row by
# up to 10 %) then moves one round, not the figure. Round r runs both with
# libFuzzer's -seed=r, so that a round draws the same mutations from one run
# of the script to the next (three 10 s runs of fuzz_controller here: 41-45 k
# exec/s with -seed=1, 38-45 k with libFuzzer's time-based seed). Prints
# every round's share and their median.
paired() {
  local t=$1 f=fuzz_floor_${1#fuzz_} r shares=()
  local -a target_flags floor_flags
  mapfile -t target_flags < <(flags_of "$t")
  mapfile -t floor_flags < <(flags_of "$t" | grep -E '^-(max_len|entropic)=')
  for ((r = 1; r <= ${ROUNDS:-5}; ++r)); do
    measure "$t.round$r" "$fuzz/$t" "${PAIR_SECONDS:-10}" "$fuzz/seeds/$t" "${target_flags[@]}" -seed="$r"
    measure "$f.round$r" "$fuzz/$f" "${PAIR_SECONDS:-10}" "$fuzz/seeds/$t" "${floor_flags[@]}" -seed="$r"
    shares+=("$(awk -v a="${per_cpu[$t.round$r]}" -v b="${per_cpu[$f.round$r]}" 'BEGIN{printf "%.2f", (b > 0) ? a / b : 0}')")
  done
  printf "%s\n" "${shares[@]}" | sort -n | awk -v n="${#shares[@]}" -v list="${shares[*]}" \
    '{v[NR] = $1} END {printf "rounds %s, median %.2f", list, (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2}'
}

# The report tool on the other core, so that it does not slow the fuzzer;
# every input cut to the target's max_len, as libFuzzer runs it.
report() {
  local max_len
  max_len=$(flags_of fuzz_controller | sed -n 's/^-max_len=//p')
  if (($(nproc) > 1)); then
    taskset -c 1 "$fuzz/fuzz_handler_report" --max-len "$max_len" "$@"
  else
    "$fuzz/fuzz_handler_report" --max-len "$max_len" "$@"
  fi
}

# until_complete LABEL LIMIT SEEDS STOP: runs fuzz_controller as
# fuzz_on_core does and reads its corpus every $poll seconds until nothing is
# missing (stopping the fuzzer then when STOP is "stop"). Sets `reached` to
# "CPU WALL" seconds when it was first complete (empty: never) and `missing`
# to what the corpus lacked last.
until_complete() {
  local label=$1 limit=$2 seeds=$3 stop=$4 start fuzzer status=0 stopped=no tck
  local -a flags
  mapfile -t flags < <(flags_of fuzz_controller)
  tck=$(getconf CLK_TCK)
  start=$(date +%s.%N)
  fuzz_on_core "$label" "$fuzz/fuzz_controller" "$limit" "$seeds" "${flags[@]}"
  reached="" missing=""
  while kill -0 "$timer" 2>/dev/null; do
    sleep "$poll"
    [[ -z $reached ]] || continue
    fuzzer=$(pgrep -P "$timer" | head -1) || true
    if missing=$(report --missing "$work/$label"); then
      # After the report: the corpus it read was there by now.
      [[ -r /proc/$fuzzer/stat ]] || break
      reached="$(awk -v t="$tck" '{printf "%.1f", ($14 + $15) / t}' "/proc/$fuzzer/stat") $(awk -v s="$start" -v n="$(date +%s.%N)" 'BEGIN{printf "%.1f", n - s}')"
      if [[ $stop == stop ]]; then
        kill -INT "$fuzzer" 2>/dev/null || true
        stopped=yes
      fi
    fi
  done
  wait "$timer" || status=$?
  finished "$label" "$status" "$stopped"
  # Complete only at the end (or between the last poll and the end): the
  # fuzzer's whole CPU time is the bound.
  if [[ -z $reached ]] && missing=$(report --missing "$work/$label"); then
    reached="$(cpu_seconds "$label") $(awk -v s="$start" -v n="$(date +%s.%N)" 'BEGIN{printf "%.1f", n - s}')"
  fi
  return 0
}

# What until_complete found, for the summary line.
time_to_all() {
  local from=$1 limit=$2
  if [[ -n $reached ]]; then
    read -r cpu wall <<<"$reached"
    echo "from $from $cpu s (wall $wall s)"
  else
    echo "from $from not reached in $limit s, ${missing}"
  fi
}

echo "build: $build ($(grep -E '^CMAKE_CXX_FLAGS:' "$build/CMakeCache.txt" | cut -d= -f2-)); $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); corpora in $tmp"
if ((exec_seconds > 0)); then
  echo
  printf "%-26s %12s %14s %10s %16s\n" target "exec/s" executions "CPU s" "exec/CPU-second"
  for t in $(cat "$fuzz/fuzz_targets.txt"); do
    mapfile -t flags < <(flags_of "$t")
    row "$t" "$fuzz/$t" "$fuzz/seeds/$t" "${flags[@]}"
  done
  # The floors (fuzz/perf_floor.cpp), with the max_len and entropic setting
  # of the matching target and libFuzzer's own mutator.
  echo "floors: libFuzzer with no oracle, its own mutator, the same instrumentation:"
  for floor in empty:fuzz_receiver receiver:fuzz_receiver controller:fuzz_controller; do
    f=fuzz_floor_${floor%%:*} t=${floor#*:}
    mapfile -t flags < <(flags_of "$t" | grep -E '^-(max_len|entropic)=')
    row "$f" "$fuzz/$f" "$fuzz/seeds/$t" "${flags[@]}"
  done
  echo "share of the floor (executions per CPU-second): in the table; then in ${ROUNDS:-5} rounds of ${PAIR_SECONDS:-10} s, target and floor side by side"
  for goal in receiver:0.7 controller:0.6; do
    t=fuzz_${goal%%:*} f=fuzz_floor_${goal%%:*}
    rounds=$(paired "$t") || { echo "$rounds"; exit 1; }  # a failed fuzzer's log
    awk -v t="$t" -v a="${per_cpu[$t]}" -v b="${per_cpu[$f]}" -v g="${goal#*:}" -v p="$rounds" \
      'BEGIN{printf "%s: %.2f of its floor; %s (goal %s)\n", t, (b > 0) ? a / b : 0, p, g}'
  done
fi

((seconds > 0)) || exit 0
echo
echo "fuzz_controller for $seconds s on one core, from its seed corpus:"
until_complete long "$seconds" "$fuzz/seeds/fuzz_controller" keep
from_seeds=$(time_to_all seeds "$seconds")
grep -E "^#[0-9]+[[:space:]]" "$work/long.log" | tail -1 | sed "s/^/  /" || true
grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added)" "$work/long.log" | sed 's/^/  /'
echo "  CPU seconds: $(cpu_seconds long)  (cov: = edges covered, ft: = features)"
echo
report_status=0
report "$work/long" || report_status=$?  # 1: replies different from the Bus's
from_empty="from empty not measured (EMPTY_SECONDS=0)"
if ((empty_seconds > 0)); then
  until_complete empty "$empty_seconds" "" stop
  from_empty=$(time_to_all empty "$empty_seconds")
fi
echo
echo "(every command ACKed and every NAK rule fired; CPU seconds of the fuzzer's core, its corpus read every $poll s)"
echo "time to all handlers and NAK rules: $from_seeds, $from_empty"
exit "$report_status"
