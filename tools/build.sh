#!/usr/bin/env bash
# Configures and builds one flavour of sabus: `tools/build.sh [main|release|sanitize|fuzz]`.
# Build trees: build/ (main, release), build-sanitize/ (ASan+UBSan), build-fuzz/ (clang, libFuzzer).
# main: sabus and its man page only, configured without tests and
# benchmarks so nothing from the test packages is needed (tools/install-deps.sh
# main); a build/ the tests were configured in keeps them configured.
# release: the same tree with everything.
set -euo pipefail
cd "$(dirname "$0")/.."
flavour=${1:-release}
case "$flavour" in
  main)     dir=build;          args=(-DCMAKE_BUILD_TYPE=Release)
            if ! grep -qx 'SABUS_BUILD_TESTS:BOOL=ON' build/CMakeCache.txt 2>/dev/null; then
              args+=(-DSABUS_BUILD_TESTS=OFF -DSABUS_BUILD_BENCHMARKS=OFF)
            fi ;;
  release)  dir=build;          args=(-DCMAKE_BUILD_TYPE=Release -DSABUS_BUILD_TESTS=ON -DSABUS_BUILD_BENCHMARKS=ON) ;;
  sanitize) dir=build-sanitize; args=(-DCMAKE_BUILD_TYPE=Debug -DSABUS_SANITIZE=ON -DSABUS_BUILD_BENCHMARKS=OFF) ;;
  # fuzz: the targets and what `ctest -L fuzz` runs, not the CLI (a quarter
  # of the tree's compile time; the live fuzzer is `sabus fuzz` of build/).
  fuzz)     dir=build-fuzz;     args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSABUS_FUZZ=ON -DSABUS_BUILD_BENCHMARKS=OFF -DSABUS_BUILD_TESTS=OFF
                                      -DSABUS_BUILD_TOOLS=OFF -DCMAKE_CXX_COMPILER=clang++-14) ;;
  *) echo "usage: tools/build.sh [main|release|sanitize|fuzz]" >&2; exit 2 ;;
esac
# ccache, where a developer has it, shares objects between build trees and
# worktrees; CI machines have none and build as before.
if command -v ccache >/dev/null; then
  args+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B "$dir" -G Ninja "${args[@]}" >/dev/null
targets=()
# The main job needs sabus and its man page only, whatever else build/ holds.
if [[ $flavour == main ]]; then targets=(--target sabus sabus_man); fi
cmake --build "$dir" -j "$(nproc)" "${targets[@]}"
