#!/bin/bash -eu
# Builds every fuzz target for ClusterFuzzLite / OSS-Fuzz into $OUT, with the
# service's compilers and flags: CC, CXX, CFLAGS, CXXFLAGS (sanitizers and
# coverage) and LIB_FUZZING_ENGINE (the engine to link). Next to each target
# it puts <target>_seed_corpus.zip (one seed per conformance vector, made by
# fuzz_seed_generator from vectors/), <target>.dict and <target>.options.
# fuzz/build_like_ossfuzz.sh runs this script locally with the same variables.
SRC_DIR=${SABUS_SRC:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}
[[ -f $SRC_DIR/CMakeLists.txt ]] || SRC_DIR=$SRC/sabus
BUILD=${WORK:-/tmp}/sabus-fuzz-build

# The libraries come from the distribution, built against libstdc++: the
# targets must use the same C++ library (the base builder's CXXFLAGS ask for
# libc++).
CXXFLAGS=${CXXFLAGS//-stdlib=libc++/}

# C++ only; CC is passed for completeness. SABUS_FUZZ_ENGINE makes every
# target link $LIB_FUZZING_ENGINE; the sanitizer flags come from CXXFLAGS.
cmake -S "$SRC_DIR" -B "$BUILD" -G Ninja \
  -DCMAKE_C_COMPILER="$CC" -DCMAKE_CXX_COMPILER="$CXX" \
  -DCMAKE_C_FLAGS="$CFLAGS" -DCMAKE_CXX_FLAGS="$CXXFLAGS" \
  -DCMAKE_BUILD_TYPE=None \
  -DSABUS_FUZZ_ENGINE="$LIB_FUZZING_ENGINE" \
  -DSABUS_BUILD_TESTS=OFF -DSABUS_BUILD_BENCHMARKS=OFF -DSABUS_BUILD_TOOLS=OFF
cmake --build "$BUILD" --target all_fuzzers fuzz_seeds -j "$(nproc)"

seeds=$BUILD/fuzz/seeds
count=0
for t in $(cat "$BUILD/fuzz/fuzz_targets.txt"); do
  cp "$BUILD/fuzz/$t" "$BUILD/fuzz/$t.options" "$OUT/"
  cp "$seeds/$t.dict" "$OUT/$t.dict"
  # The seed corpus: one seed per vector, plus the findings kept in the
  # repository as regression seeds.
  corpus=$BUILD/fuzz/corpus-$t
  rm -rf "$corpus" "$OUT/${t}_seed_corpus.zip"
  mkdir -p "$corpus"
  cp "$seeds/$t"/* "$corpus/"
  if [[ -d $SRC_DIR/fuzz/regressions/$t ]]; then
    for f in "$SRC_DIR/fuzz/regressions/$t"/*; do [[ -f $f ]] && cp "$f" "$corpus/regression-$(basename "$f")"; done
  fi
  (cd "$corpus" && cmake -E tar cf "$OUT/${t}_seed_corpus.zip" --format=zip -- *)
  count=$((count + 1))
done
echo "build.sh: $count fuzz targets in $OUT"
