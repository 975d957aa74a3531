#!/usr/bin/env bash
# Renders the HTML report of a failing run in headless Chromium and checks
# what a person sees: the verdict and the summary line, both charts (reply
# time per command, the coverage heat map with a cell per row and path), and
# the filter: the page's script runs under its Content-Security-Policy,
# reads the filter from the query string as a person's choice would set it,
# and hides exactly the vectors that do not match, also the vectors in error
# (the line left them unjudged) of the same run. Screenshots go to WORK
# (their paths are printed). Exit 77 (skipped) only when Chromium is not
# installed (tools/install-deps.sh installs it).
set -euo pipefail
sabus=$1
work=$2
chromium=/usr/bin/chromium
if [[ ! -x $chromium ]]; then
  echo "SKIP: $chromium is not installed (tools/install-deps.sh installs it)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work"
"$sabus" run --sim --fault short-status --report-dir "$work/run" >"$work/console.txt" 2>&1 || true
html=$work/run/report.html
# The summary the HTML must show is the run's own summary line (the line
# figures and the verdict's reasons may follow it).
summary=$(grep -E '^[0-9]+ passed, ' "$work/console.txt" | tail -n 1)
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# Without the background-networking switches Chromium dials out at start,
# which a closed network refuses.
browse() {
  timeout 90 "$chromium" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync --user-data-dir="$profile" "$@" 2>/dev/null
}
fail=0
check() {  # check WHAT CONDITION...
  local what=$1
  shift
  if ! "$@"; then
    echo "FAIL: $what"
    fail=1
  fi
}
has() { grep -qF -- "$1" <<<"$2"; }

dom=$(browse --dump-dom "file://$html")
for want in "<p id=\"summary\">$summary</p>" 'id="verdict">FAIL<' 'id="coverage"' '3.2-status-reply-length' \
            'sabus-run v7' '<svg id="chart-turnaround"' '<svg id="chart-coverage"'; do
  check "the rendered DOM has $want" has "$want" "$dom"
done
# The heat map has a cell per coverage row and path, and cells of both colours.
rows=$(grep -c '^<tr><td><code>' <<<"$dom" || true)
cells=$(grep -o '<rect class="cell [a-z]*"' <<<"$dom" | wc -l)
check "the coverage heat map has $((rows * 4)) cells ($rows rows × 4 paths), got $cells" test "$cells" -eq $((rows * 4))
check "the heat map shows passes and failures" has '<rect class="cell fail"' "$dom"
check "the heat map shows passes and failures" has '<rect class="cell pass"' "$dom"
bars=$(grep -o '<g class="bar">' <<<"$dom" | wc -l)
check "the reply-time chart has a bar per command that was answered (got $bars)" test "$bars" -ge 2
# The script ran: it shows the filter and counts the vectors.
total=$(grep -o '<details class="v"' "$html" | wc -l)
check "the script shows the filter (the CSP hash lets it run)" has '<form id="filter" data-shown=' "$dom"
check "every vector is shown unfiltered" has "<output id=\"shown\">$total of $total vectors shown</output>" "$dom"

# The filter as a person sets it: failed must vectors of §3.2.
filter='status=fail&level=must&paragraph=3.2'
match='data-status="fail" data-level="must" data-paragraph="3.2"'
expected=$(grep -o "<details class=\"v\" id=\"[^\"]*\" $match" "$html" | wc -l)
check "the run has failed must vectors of §3.2 to filter ($expected of $total)" test "$expected" -gt 0 -a "$expected" -lt "$total"
filtered=$(browse --dump-dom "file://$html?$filter")
shown=$(grep -o '<details class="v"[^>]*>' <<<"$filtered" | grep -v ' hidden=""' || true)
shown_count=$(grep -c . <<<"$shown" || true)
check "?$filter shows $expected vectors, got $shown_count" test "$shown_count" -eq "$expected"
check "?$filter shows only vectors that match" test -z "$(grep -vF -- "$match" <<<"$shown" || true)"
check "?$filter counts what it shows" has "<output id=\"shown\">$expected of $total vectors shown</output>" "$filtered"

browse --window-size=1280,3000 --screenshot="$work/report.png" "file://$html" >/dev/null
# Tall enough to reach the vectors the filter leaves.
browse --window-size=1280,7000 --screenshot="$work/report-filtered.png" "file://$html?$filter" >/dev/null
for png in "$work/report.png" "$work/report-filtered.png"; do
  check "a screenshot was written to $png" test -s "$png"
done

# A controller that gets its framing wrong (issue 21: its check bytes are
# wrong, so nothing it says decodes and the run aborts): the page of that run
# renders too, says ABORTED, and shows the receiver's reason as text.
"$sabus" run --sim --fault lrc-skips-byte0 --report-dir "$work/framing" >"$work/framing.txt" 2>&1 || true
framing=$(browse --dump-dom "file://$work/framing/report.html")
check "the framing run's page says ABORTED" has 'id="verdict">ABORTED<' "$framing"
check "the framing run's page shows why its replies were ignored" has "bad LRC: check byte 0x" "$framing"
check "the framing run's script ran" has '<form id="filter" data-shown=' "$framing"
# Vectors the line left unjudged (the error outcome): two passing vectors of
# the run recorded in error, as the runner records them on a noisy line, and
# the page `sabus report` makes of that JSON: the filter ?status=error shows
# exactly those two, and the page shows the run's line figures.
/usr/bin/python3 - "$work/run/run.json" "$work/errors.json" <<'PY'
import json, sys
run = json.load(open(sys.argv[1]))
erred = [v for v in run["vectors"] if v["outcome"] == "pass"][:2]
for v in erred:
    v.update(outcome="error", error_reason="step 1 (status): no clean reply in 2 tries: bad check byte",
             line={"exchanges": 2, "faults": 2, "recovered": 0, "repeats": 1})
s = run["summary"]
s["passed"] -= len(erred)
s["errors"] = len(erred)
s["line"] = {"exchanges": 1412, "faults": 3, "recovered": 1, "repeats": 2}
json.dump(run, open(sys.argv[2], "w"))
PY
"$sabus" report "$work/errors.json" --html "$work/errors.html" >/dev/null
errors=$(browse --dump-dom "file://$work/errors.html?status=error")
shown=$(grep -o '<details class="v"[^>]*>' <<<"$errors" | grep -v ' hidden=""' || true)
check "?status=error shows the 2 vectors in error, got $(grep -c . <<<"$shown" || true)" test "$(grep -c . <<<"$shown" || true)" -eq 2
check "?status=error shows only vectors in error" test -z "$(grep -vF 'data-status="error"' <<<"$shown" || true)"
check "the page with errors shows the run's line figures" has '<p id="line">line: 3 faults in 1,412 exchanges, 1 recovered (fault rate 0.21%)</p>' "$errors"
check "the page with errors shows what the line did" has 'error: step 1 (status): no clean reply in 2 tries: bad check byte' "$errors"
browse --window-size=1280,3000 --screenshot="$work/report-errors.png" "file://$work/errors.html?status=error" >/dev/null
check "a screenshot was written to $work/report-errors.png" test -s "$work/report-errors.png"

if [[ $fail == 0 ]]; then
  echo "rendered: $(grep -o '<p id="summary">[^<]*' <<<"$dom" | sed 's/<[^>]*>//')"
  echo "filter ?$filter: $expected of $total vectors shown"
  echo "charts: reply time per command ($bars commands), coverage heat map ($rows rows, $cells cells)"
  echo "filter ?status=error: 2 vectors in error shown"
  echo "screenshots: $work/report.png $work/report-filtered.png $work/report-errors.png"
fi
exit $fail
