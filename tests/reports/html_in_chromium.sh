#!/usr/bin/env bash
# Renders the HTML report of a failing run in headless Chromium and checks
# that the DOM holds the verdict and the summary line. Exit 77 (skipped)
# when Chromium is not installed: `apt-get install chromium` (README).
set -euo pipefail
sabus=$1
work=$2
chromium=/usr/bin/chromium
if [[ ! -x $chromium ]]; then
  echo "SKIP: $chromium is not installed"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work"
"$sabus" run --sim --fault short-status --html "$work/report.html" >"$work/console.txt" 2>&1 || true
# The summary the HTML must show is the run's own closing line.
summary=$(tail -n 1 "$work/console.txt")
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
dom=$(timeout 90 "$chromium" --headless --no-sandbox --disable-gpu --disable-background-networking \
  --disable-component-update --disable-sync --no-first-run --user-data-dir="$profile" \
  --dump-dom "file://$work/report.html" 2>/dev/null)
fail=0
for want in "<p id=\"summary\">$summary</p>" 'id="verdict">FAIL<' 'id="coverage"' \
            '3.2-status-reply-length'; do
  if ! grep -qF -- "$want" <<<"$dom"; then
    echo "FAIL: the rendered DOM has no $want"
    fail=1
  fi
done
[[ $fail == 0 ]] && echo "rendered: $(grep -o '<p id="summary">[^<]*' <<<"$dom")"
exit $fail
