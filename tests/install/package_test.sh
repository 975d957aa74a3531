#!/usr/bin/env bash
# The Debian package: built with CPack from the build tree, unpacked into a
# fresh prefix (dpkg-deb -x, as dpkg would lay it out under /), and run from
# there: `man sabus` shows its man page (man_test.sh), `sabus --version` finds the data of that prefix, `sabus vectors lint`
# passes, `sabus run --sim` runs the suite and passes, and its reports carry
# the version. Prints the package's name, size, file count and Depends
# ("package:" lines, which tools/run-tests.sh shows).
#   tests/install/package_test.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$(realpath "$1")
work=$2
rm -rf "$work"
mkdir -p "$work"
work=$(realpath "$work")

fail() {
  echo "package test: $*" >&2
  exit 1
}

cpack --config "$build/CPackConfig.cmake" -G DEB -B "$work/out" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log"; fail "cpack -G DEB failed"; }
debs=("$work"/out/*.deb)
[[ ${#debs[@]} -eq 1 && -f ${debs[0]} ]] || fail "expected one .deb in $work/out, found: ${debs[*]}"
deb=${debs[0]}

# Depends: from dpkg-shlibdeps, the libraries the binary links.
depends=$(dpkg-deb --field "$deb" Depends)
for lib in libyaml-cpp libserialport libfmt libstdc++6 libc6; do
  [[ $depends == *"$lib"* ]] || fail "Depends lacks $lib: $depends"
done
# Every file under /usr.
outside=$(dpkg-deb --contents "$deb" | awk '{print $6}' | grep -v '^\./usr/' | grep -v '^\./$' || true)
[[ -z $outside ]] || fail "files outside /usr: $outside"

dpkg-deb -x "$deb" "$work/root"
prefix=$work/root/usr
sabus=$prefix/bin/sabus
files=$(find "$work/root" -type f | wc -l)
echo "package: $(basename "$deb"), $(stat -c %s "$deb") bytes, $files files, installed size $(dpkg-deb --field "$deb" Installed-Size) KiB"
echo "package: Depends: $depends"
echo "package: files by folder:"
(cd "$work/root" && find . -type f | awk -F/ '{d = $2 "/" $3 "/" $4; if ($4 == "sabus" && NF > 5) d = d "/" $5; n[d]++} END {for (d in n) printf "package:   %4d %s\n", n[d], d}' | sort -k3)

# The man page, sabus(1), as `man` finds it in the unpacked package.
bash "$(dirname "$0")/man_test.sh" "$prefix" package || fail "man sabus from the package"
[[ -f $prefix/share/doc/sabus/docs/bench-acceptance.md ]] || fail "the package lacks the guides (share/doc/sabus/docs/)"

# Run from a directory outside the source tree, with no data directory
# given: the data must be the prefix's own.
cd "$work"
unset SABUS_DATA_DIR
version=$("$sabus" --version) || fail "sabus --version failed"
echo "$version" | sed 's/^/package: /'
[[ $(head -1 <<<"$version") == "$("$build/tools/sabus" --version | head -1)" ]] ||
  fail "the packaged sabus --version differs from the build's: $version"
[[ $version == *"data: $prefix/share/sabus (installed beside the executable)"* ]] ||
  fail "the packaged sabus does not take its data from $prefix/share/sabus: $version"

lint=$("$sabus" vectors lint) || { echo "$lint"; fail "sabus vectors lint failed"; }
echo "package: sabus vectors lint: $(tail -1 <<<"$lint")"
[[ $(tail -1 <<<"$lint") =~ ^[0-9]+\ files,\ [1-9][0-9]*\ vectors,\ 0\ errors$ ]] || fail "lint: $lint"

run=$("$sabus" run --sim --report-dir "$work/report") || { echo "$run"; fail "sabus run --sim failed"; }
echo "package: sabus run --sim: $(tail -1 <<<"$run")"
[[ $(tail -1 <<<"$run") =~ ^[1-9][0-9]*\ passed,\ 0\ failed ]] || fail "run: $run"

# The version in every report.
full="sabus ${version#sabus }"
full=$(head -1 <<<"$full")
grep -qF "\"generator\": \"$full\"" "$work/report/run.json" || grep -qF "\"generator\":\"$full\"" "$work/report/run.json" ||
  fail "run.json does not carry \"$full\""
for report in junit.xml report.html summary.md; do
  grep -qF "$full" "$work/report/$report" || fail "$report does not carry \"$full\""
done
echo "package: reports carry \"$full\""
