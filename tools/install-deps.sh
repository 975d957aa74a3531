#!/usr/bin/env bash
# Installs the dependencies of sabus from Debian 12 packages:
#   tools/install-deps.sh main   what the main job needs: build sabus (tests
#                                off) and run it (tools/run-main.sh)
#   tools/install-deps.sh test   the main packages and what only the tests,
#                                the fuzz build and the package test use
#                                (tools/run-tests.sh); the default
# One list, each package once, tagged with the job that needs it.
# Idempotent: apt-get runs only when a package is missing.
set -euo pipefail

job=${1:-test}
case "$job" in
  main|test) ;;
  *) echo "usage: tools/install-deps.sh [main|test]" >&2; exit 2 ;;
esac

# "JOB PACKAGE...  # why": main packages are also installed for the tests.
table='
main build-essential g++ cmake ninja-build pkg-config
main libserialport-dev                     # serial transport
main libyaml-cpp-dev                       # vectors and device profiles
main libcli11-dev                          # command-line parsing of the sabus CLI
main libfmt-dev                            # formatting
main nlohmann-json3-dev                    # JSON: reading run files and journals, state files, the proxy log, --json output
main rapidjson-dev                         # JSON: the run JSON and journal writer (streaming) and strict reader
test clang-14 libclang-rt-14-dev           # libFuzzer and the sanitizer runtimes
test libgtest-dev libgmock-dev             # unit tests
test librapidcheck-dev                     # property tests
test libbenchmark-dev                      # receiver throughput benchmark
test libvalijson-dev                       # JSON Schema: the run JSON and journal checked against reports/run.schema.json (pulls in Qt 5 and Poco)
test libxml2-dev                           # JUnit: checked against reports/junit.xsd in-process (tests, gate, fuzz_record)
test libgumbo-dev                          # HTML5 parser: the HTML report parsed in the tests and fuzz_record
test libcmark-gfm-dev libcmark-gfm-extensions-dev  # GitHub Markdown parser: summary.md parsed in the tests and fuzz_record
test socat                                 # pty pairs for integration tests
test libxml2-utils                         # xmllint: the JUnit report validates against reports/junit.xsd
test dpkg-dev file                         # cpack -G DEB: dpkg-shlibdeps computes the package Depends
test man-db                                # man -l: the installed and packaged man page (tests/install)
test python3 python3-yaml                   # the documentation tests: transcripts, generated reference (tools/docs/)
test chromium                              # headless: the HTML report test renders it (tests/reports)
test time                                  # /usr/bin/time: peak memory in tools/journal-bench.sh
test bc                                    # arithmetic of tools/journal-bench.sh and tools/perf-run.sh
test ser2net                               # a real RFC 2217 terminal server in front of `sabus sim --pty` (tests/tools)
test python3-serial                        # pyserial rfc2217:// client against `sabus sim --rfc2217` (/usr/bin/python3)
'

packages=()
while read -r tag rest; do
  [[ -z $tag ]] && continue
  [[ $tag == main || $job == test ]] || continue
  rest=${rest%%#*}
  read -ra names <<<"$rest"
  packages+=("${names[@]}")
done <<<"$table"

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-deps ($job): all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps ($job): installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
