#!/usr/bin/env bash
# Rewrites the generated parts of the documents after vectors or the CLI change:
# the table by paragraph in vectors/README.md (sabus vectors list --summary)
# and, in protocol/ERRATA.md, the Vectors line of every entry and the index
# table at the top (id, title, class, level, switch); and docs/reference/.
# Tests check each.
set -euo pipefail
cd "$(dirname "$0")/.."
sabus=${SABUS:-build/tools/sabus}
table=$(mktemp)
trap 'rm -f "$table"' EXIT
"$sabus" vectors list --summary >"$table"
awk -v table="$table" '
  /<!-- suite-summary:begin -->/ { print; while ((getline line < table) > 0) print line; skip = 1; next }
  /<!-- suite-summary:end -->/ { skip = 0 }
  !skip { print }
' vectors/README.md >vectors/README.md.new
mv vectors/README.md.new vectors/README.md
"$sabus" vectors errata --update protocol/ERRATA.md
# The reference pages generated from the code (docs/reference/): the CLI's
# --help, the faults, the vector file keys, the profile keys, the run JSON
# schema, the errata index.
/usr/bin/python3 tools/docs/reference.py --sabus "$sabus" --source .
