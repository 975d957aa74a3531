#!/usr/bin/env bash
# The main job: installs what is missing, builds, and decodes the manual's
# example frames with `sabus decode`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
bash tools/build.sh release
build/tools/sabus decode --side both vectors/examples/manual-examples.hex
