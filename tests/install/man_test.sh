#!/usr/bin/env bash
# sabus(1) from an installed prefix: `man -l` reads the installed file, and
# `MANPATH=PREFIX/share/man man sabus` finds it; both show the NAME line and
# every subcommand the prefix's own `sabus --help` lists, with its options
# (the page is made from that help, cmake/man_page.sh).
#   tests/install/man_test.sh PREFIX [LABEL]
set -euo pipefail
prefix=$1 label=${2:-man}
page=$prefix/share/man/man1/sabus.1.gz
fail() {
  echo "$label: $*" >&2
  exit 1
}
[[ -f $page ]] || fail "no $page"
by_file=$(MANWIDTH=100 man -l -P cat "$page" 2>&1) || fail "man -l $page failed: $by_file"
by_name=$(MANPATH=$prefix/share/man MANWIDTH=100 man -P cat sabus 2>&1) || fail "MANPATH=$prefix/share/man man sabus failed: $by_name"
[[ $by_file == "$by_name" ]] || fail "man -l and MANPATH= man sabus show different pages"
grep -q "sabus - SAbus conformance and fuzz test harness" <<<"$by_name" || fail "no NAME line: $(head -5 <<<"$by_name")"
subs=$("$prefix/bin/sabus" --help | awk '/^(SUBCOMMANDS|Subcommands):/ { i = 1; next } i && /^  [^ ]/ { print $1; next } i && /^[^ ]/ { i = 0 }')
[[ -n $subs ]] || fail "sabus --help lists no subcommands"
for sub in $subs; do
  grep -q "^   sabus $sub\$" <<<"$by_name" || fail "no section for sabus $sub"
done
# An option of each kind the page must carry as the help does.
for option in --allow-motion --paragraph --list-faults --fresh-device --timing-threshold; do
  grep -qF -- "$option" <<<"$by_name" || fail "the page lacks $option"
done
echo "$label: man sabus from $prefix/share/man: $(wc -l <<<"$by_name") lines, $(wc -w <<<"$subs") subcommands"
