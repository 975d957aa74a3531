#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the conformance
# suite (vectors/) against the built-in reference controller, writing
# build/report/run.json, junit.xml, report.html and summary.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh release
build/tools/sabus run --sim --allow-motion --allow-destructive --report-dir build/report
