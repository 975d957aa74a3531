#!/usr/bin/env bash
# tools/docs/transcripts.py on tests/docs/drift.md must fail, naming the
# drifted command and the unknown option, and pass the block that did not
# drift.
#   tests/docs/drift_test.sh PYTHON TRANSCRIPTS_PY SABUS SOURCE DRIFT_MD WORK
set -uo pipefail
python=$1 script=$2 sabus=$3 source=$4 page=$5 work=$6
out=$("$python" "$script" --sabus "$sabus" --source "$source" --work "$work" "$page" 2>&1)
status=$?
echo "$out"
fail() {
  echo "drift test: $*" >&2
  exit 1
}
[[ $status -eq 1 ]] || fail "expected exit 1, got $status"
grep -q 'drift.md:13: \$ sabus run --paragraph 3.1$' <<<"$out" || fail "the drifted block is not named"
grep -q '^-N passed, N failed, N skipped$' <<<"$out" || fail "the shown line is not in the diff"
grep -q 'no option --no-such-option' <<<"$out" || fail "the unknown option is not named"
grep -q 'drift.md:7: ' <<<"$out" && fail "the block that did not drift was reported"
grep -q '^transcripts: 2 run, 1 not run (options checked), 2 error(s)' <<<"$out" || fail "summary"
echo "drift test: pass"
