#!/usr/bin/env bash
# Runs .clusterfuzzlite/build.sh as the OSS-Fuzz base builder would (the
# service's Docker image cannot run here): CC, CXX, CFLAGS, CXXFLAGS,
# LIB_FUZZING_ENGINE, SRC, WORK and OUT set as base-builder sets them for
# libFuzzer, with clang-14. Then checks that $OUT has every target of
# fuzz_targets.txt with its seed-corpus zip, .dict and .options, that
# each target runs its seed corpus, and that each one runs a few seconds from
# an empty corpus (run_empty_corpus.sh).
#   fuzz/build_like_ossfuzz.sh [OUT_DIR]     (SANITIZER=address|undefined, default address)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export OUT=${1:-$root/build-ossfuzz/out}
export WORK=${WORK:-$(dirname "$OUT")/work}
export SRC=$root/..
export SABUS_SRC=$root
mkdir -p "$OUT" "$WORK"
export CC=clang-14 CXX=clang++-14
sanitizer=${SANITIZER:-address}
case "$sanitizer" in
  address)   san="-fsanitize=address -fsanitize-address-use-after-scope" ;;
  undefined) san="-fsanitize=array-bounds,bool,builtin,enum,float-divide-by-zero,function,integer-divide-by-zero,null,object-size,return,returns-nonnull-attribute,shift,signed-integer-overflow,unsigned-integer-overflow,unreachable,vla-bound,vptr -fno-sanitize-recover=array-bounds,bool,builtin,enum,float-divide-by-zero,function,integer-divide-by-zero,null,object-size,return,returns-nonnull-attribute,shift,signed-integer-overflow,unreachable,vla-bound,vptr" ;;
  *) echo "SANITIZER must be address or undefined" >&2; exit 2 ;;
esac
# base-builder's flags: COVERAGE_FLAGS + SANITIZER_FLAGS + CFLAGS; CXXFLAGS adds libc++.
export CFLAGS="-O1 -fno-omit-frame-pointer -gline-tables-only -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION $san -fsanitize=fuzzer-no-link"
export CXXFLAGS="$CFLAGS -stdlib=libc++"
export LIB_FUZZING_ENGINE=-fsanitize=fuzzer
export FUZZING_ENGINE=libfuzzer SANITIZER=$sanitizer ARCHITECTURE=x86_64
bash "$root/.clusterfuzzlite/build.sh"

targets=$(cat "$WORK/sabus-fuzz-build/fuzz/fuzz_targets.txt")
missing=0 n=0
for t in $targets; do
  n=$((n + 1))
  for f in "$t" "${t}_seed_corpus.zip" "$t.dict" "$t.options"; do
    if [[ ! -s $OUT/$f ]]; then echo "MISSING in \$OUT: $f"; missing=1; fi
  done
  [[ -x $OUT/$t ]] || { echo "NOT EXECUTABLE: $OUT/$t"; missing=1; }
  grep -q "^\[libfuzzer\]" "$OUT/$t.options" || { echo "BAD OPTIONS: $OUT/$t.options"; missing=1; }
  # Each target runs its seed corpus, as the service's first run does.
  corpus=$WORK/check-$t
  rm -rf "$corpus" && mkdir -p "$corpus"
  (cd "$corpus" && cmake -E tar xf "$OUT/${t}_seed_corpus.zip")
  seeds=$(find "$corpus" -type f | wc -l)
  if ! "$OUT/$t" -runs=0 -dict="$OUT/$t.dict" "$corpus" >"$corpus.log" 2>&1; then
    tail -20 "$corpus.log"; echo "TARGET FAILED on its seed corpus: $t"; missing=1
  else
    echo "ok: $t ($seeds seeds, $(grep -o 'cov: [0-9]*' "$corpus.log" | tail -1))"
  fi
  # And from nothing, as the service's bad-build check and a job without a
  # stored corpus run it.
  bash "$root/fuzz/run_empty_corpus.sh" "$OUT/$t" "$OUT/$t.options" || missing=1
done
if ((n == 0)); then echo "no targets listed"; exit 1; fi
# The service's CXXFLAGS instrument everything; the targets still get
# coverage from their code under test only (fuzz/README.md).
bash "$root/fuzz/check_instrumentation.sh" "$OUT/fuzz_receiver" 100 2000 || missing=1
if ((missing)); then echo "build_like_ossfuzz: FAILED"; exit 1; fi
echo "build_like_ossfuzz: $n targets, each with its seed corpus zip, .dict and .options in $OUT"
