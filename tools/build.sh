#!/usr/bin/env bash
# Configures and builds one flavour of sabus: `tools/build.sh [release|sanitize|fuzz]`.
# Build trees: build/ (release), build-sanitize/ (ASan+UBSan), build-fuzz/ (clang, libFuzzer).
set -euo pipefail
cd "$(dirname "$0")/.."
flavour=${1:-release}
case "$flavour" in
  release)  dir=build;          args=(-DCMAKE_BUILD_TYPE=Release) ;;
  sanitize) dir=build-sanitize; args=(-DCMAKE_BUILD_TYPE=Debug -DSABUS_SANITIZE=ON -DSABUS_BUILD_BENCHMARKS=OFF) ;;
  fuzz)     dir=build-fuzz;     args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSABUS_FUZZ=ON -DSABUS_BUILD_BENCHMARKS=OFF -DSABUS_BUILD_TESTS=OFF
                                      -DCMAKE_CXX_COMPILER=clang++-14) ;;
  *) echo "usage: tools/build.sh [release|sanitize|fuzz]" >&2; exit 2 ;;
esac
# ccache, where a developer has it, shares objects between build trees and
# worktrees; CI machines have none and build as before.
if command -v ccache >/dev/null; then
  args+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B "$dir" -G Ninja "${args[@]}" >/dev/null
cmake --build "$dir" -j "$(nproc)"
