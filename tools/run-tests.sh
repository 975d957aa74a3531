#!/usr/bin/env bash
# Every test: installs what is missing (tools/install-deps.sh test: the main
# packages and the test-only ones), builds the release and the sanitizer
# (ASan+UBSan) flavours, and runs the whole ctest suite in both (the release
# suite builds the Debian package and runs it from a fresh prefix); with clang
# present it also builds the libFuzzer targets, runs each for FUZZ_SECONDS
# (default 30) from its seed corpus and 5 s from an empty one, and builds
# them as ClusterFuzzLite does (fuzz/build_like_ossfuzz.sh).
# Ends with one line "tests: N passed, N failed" over all runs, and exits
# non-zero when any test failed.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh test
bash tools/build.sh release
bash tools/build.sh sanitize

passed=0 failed=0 status=0
# run_ctest TITLE ARGS...: runs ctest, adds its counts to the totals.
run_ctest() {
  local title=$1 log
  shift
  log=$(mktemp)
  echo "== $title"
  if ! ctest "$@" --output-on-failure 2>&1 | tee "$log"; then status=1; fi
  local line total bad
  line=$(grep -E "tests passed, [0-9]+ tests failed out of [0-9]+" "$log" | tail -1 || true)
  if [[ -z $line ]]; then
    echo "== $title: ctest printed no summary"
    status=1
  else
    bad=$(sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\1/' <<<"$line")
    total=$(sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\2/' <<<"$line")
    passed=$((passed + total - bad))
    failed=$((failed + bad))
  fi
  rm -f "$log"
}

run_ctest "release build" --test-dir build -j "$(nproc)"
# The vector suite's gates (ctest -L gate): their figures, from ctest's log.
grep -hE "^(mutation score:|records:|suite gates:|[0-9]+ of [0-9]+ cells covered)" build/Testing/Temporary/LastTest.log || true
# The Debian package, unpacked into a fresh prefix and run from there (ctest
# -L install, tests/install/package_test.sh): its size, files, Depends, and
# what its sabus printed.
grep -h "^package: " build/Testing/Temporary/LastTest.log || true
# One slot more than cores: about 560 s of this suite are the pty and TCP
# tests (cli.sweep.five_profiles_over_a_pty, cli.sim.line_faults_over_a_pty,
# cli.rfc2217.ser2net, Run.OverAPty…, Run.OverTcp), which wait on the line at
# its pace and leave their core idle; the release suite is bound by gate.suite
# on one core and keeps one slot per core.
run_ctest "sanitizer build (ASan+UBSan)" --test-dir build-sanitize -j "$(($(nproc) + 1))"
if command -v clang++-14 >/dev/null; then
  bash tools/build.sh fuzz
  run_ctest "libFuzzer build, ${FUZZ_SECONDS:-30} s per target, and the ClusterFuzzLite build" --test-dir build-fuzz -L fuzz -j "$(nproc)"
fi
echo "tests: $passed passed, $failed failed"
if ((failed > 0)); then status=1; fi
exit $status
