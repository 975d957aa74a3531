#!/usr/bin/env bash
# Every test: installs what is missing, builds the release and the sanitizer
# (ASan+UBSan) flavours, and runs the whole ctest suite in both; with clang
# present it also builds the libFuzzer targets and runs their smoke tests.
# Exits non-zero when any test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh release
bash tools/build.sh sanitize
status=0
echo "== release build: ctest"
ctest --test-dir build --output-on-failure -j "$(nproc)" || status=1
echo "== sanitizer build (ASan+UBSan): ctest"
ctest --test-dir build-sanitize --output-on-failure -j "$(nproc)" || status=1
if command -v clang++-14 >/dev/null; then
  bash tools/build.sh fuzz
  echo "== libFuzzer build: ctest -L fuzz"
  ctest --test-dir build-fuzz --output-on-failure -L fuzz -j "$(nproc)" || status=1
fi
exit $status
