#!/usr/bin/env bash
# The main job: installs what is missing (tools/install-deps.sh main: the
# build and what sabus links, no test packages), builds sabus (tools/build.sh
# main: no tests), and runs the conformance
# suite (vectors/) against the built-in reference controller, writing
# build/report/run.json, junit.xml, report.html and summary.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh main
bash tools/build.sh main
build/tools/sabus run --sim --allow-motion --allow-destructive --report-dir build/report
