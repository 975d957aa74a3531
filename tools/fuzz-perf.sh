#!/usr/bin/env bash
# Prints the fuzz targets' speed on one core and what the whole-controller
# target reaches in a given time (figures are printed, never asserted):
#   tools/fuzz-perf.sh [SECONDS]     (SECONDS=0: only step 1)
# 1. every target runs EXEC_SECONDS (default 20; 0 skips this) from its seed corpus, pinned
#    to one core (taskset -c 0): libFuzzer's exec/s, and executions per
#    CPU-second of the process (the same figure on a machine shared with
#    other jobs, where wall-clock exec/s understates the target);
# 2. fuzz_controller runs SECONDS (default 300) from its seed corpus on one
#    core: its final edge coverage, then fuzz_handler_report replays the
#    resulting corpus and lists the command handlers (and forms, and NAK
#    rules) the corpus reaches.
# Step 1 also runs the floors (fuzz/perf_floor.cpp): libFuzzer with a target
# that does nothing, the receiver fed once and the controller executing
# frames, both without an oracle -- what the targets' speeds compare with.
# BUILD (default build-fuzz-perf): the build tree of the targets. Made here
# when missing: libFuzzer without sanitizers (-fsanitize=fuzzer through
# SABUS_FUZZ_ENGINE), the engine's own speed. BUILD=build-fuzz measures the
# ASan+UBSan flavour the tests run (tools/build.sh fuzz).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-300}
exec_seconds=${EXEC_SECONDS:-20}
build=${BUILD:-build-fuzz-perf}
if [[ ! -f $build/build.ninja ]]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
    -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link" -DSABUS_FUZZ_ENGINE=-fsanitize=fuzzer \
    -DSABUS_BUILD_TESTS=OFF -DSABUS_BUILD_BENCHMARKS=OFF -DSABUS_BUILD_TOOLS=OFF >/dev/null
fi
cmake --build "$build" --target all_fuzzers fuzz_handler_report fuzz_seeds fuzz_floors >/dev/null
fuzz=$build/fuzz
work=$(mktemp -d "${TMPDIR:-/tmp}/sabus-fuzz-perf.XXXXXX")
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

# fuzz_on_core LABEL BINARY SECONDS SEEDS FLAGS...: runs BINARY for SECONDS on
# core 0 from a copy of SEEDS (left in $work/LABEL) with FLAGS; its output
# goes to $work/LABEL.log, its user and system CPU time to $work/LABEL.time.
fuzz_on_core() {
  local label=$1 binary=$2 limit=$3 seeds=$4
  shift 4
  mkdir -p "$work/$label"
  cp "$seeds"/* "$work/$label/"
  /usr/bin/time -f "%U %S" -o "$work/$label.time" taskset -c 0 "$binary" "$@" -max_total_time="$limit" \
    -print_final_stats=1 -artifact_prefix="$work/" "$work/$label" >"$work/$label.log" 2>&1 || {
    echo "$label failed:"; tail -30 "$work/$label.log"; exit 1; }
}

cpu_seconds() { awk '{printf "%.1f", $1 + $2}' "$work/$1.time"; }

# row LABEL BINARY SEEDS FLAGS...: one row of the table, EXEC_SECONDS of
# BINARY: libFuzzer's exec/s and executions per CPU-second.
row() {
  local label=$1 binary=$2 seeds=$3 rate runs cpu
  shift 3
  fuzz_on_core "$label" "$binary" "$exec_seconds" "$seeds" "$@"
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$work/$label.log")
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/$label.log")
  cpu=$(cpu_seconds "$label")
  printf "%-22s %12s %14s %10s %16s\n" "$label" "$rate" "$runs" "$cpu" \
    "$(awk -v r="$runs" -v c="$cpu" 'BEGIN{printf "%d", (c > 0) ? r / c : 0}')"
}

echo "build: $build ($(grep -E '^CMAKE_CXX_FLAGS:' "$build/CMakeCache.txt" | cut -d= -f2-)); $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
if ((exec_seconds > 0)); then
  echo
  printf "%-22s %12s %14s %10s %16s\n" target "exec/s" executions "CPU s" "exec/CPU-second"
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
fi

((seconds > 0)) || exit 0
echo
echo "fuzz_controller for $seconds s on one core, from its seed corpus:"
mapfile -t flags < <(flags_of fuzz_controller)
fuzz_on_core long "$fuzz/fuzz_controller" "$seconds" "$fuzz/seeds/fuzz_controller" "${flags[@]}"
grep -E "^#[0-9]+[[:space:]]" "$work/long.log" | tail -1 | sed "s/^/  /" || true
grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added)" "$work/long.log" | sed 's/^/  /'
echo "  CPU seconds: $(cpu_seconds long)  (cov: = edges covered, ft: = features)"
echo
"$fuzz/fuzz_handler_report" "$work/long"
