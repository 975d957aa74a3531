#!/usr/bin/env bash
# Installs every build and test dependency of sabus from Debian 12 packages.
# Idempotent: apt-get runs only when a package is missing.
set -euo pipefail

packages=(
  build-essential g++ cmake ninja-build pkg-config
  clang-14 libclang-rt-14-dev           # libFuzzer and the sanitizer runtimes
  libgtest-dev libgmock-dev             # unit tests
  librapidcheck-dev                     # property tests
  libbenchmark-dev                      # receiver throughput benchmark
  libserialport-dev                     # serial transport (later issues)
  libyaml-cpp-dev                       # vectors and device profiles
  libcli11-dev                          # command-line parsing of the sabus CLI
  libfmt-dev                            # formatting
  nlohmann-json3-dev                    # JSON: reading run files and journals, state files, the proxy log, --json output
  rapidjson-dev                         # JSON: the run JSON and journal writer (streaming) and strict reader
  libvalijson-dev                       # JSON Schema: the run JSON and journal checked against reports/run.schema.json
  libxml2-dev                           # JUnit: checked against reports/junit.xsd in-process (tests, gate, fuzz_record)
  libgumbo-dev                          # HTML5 parser: the HTML report parsed in the tests and fuzz_record
  libcmark-gfm-dev libcmark-gfm-extensions-dev  # GitHub Markdown parser: summary.md parsed in the tests and fuzz_record
  socat                                 # pty pairs for integration tests
  libxml2-utils                         # xmllint: the JUnit report validates against reports/junit.xsd
  dpkg-dev file                         # cpack -G DEB: dpkg-shlibdeps computes the package's Depends
  chromium                              # headless: the HTML report's test renders it (tests/reports)
  time                                  # /usr/bin/time: peak memory in tools/journal-bench.sh
  bc                                    # arithmetic of tools/journal-bench.sh and tools/perf-run.sh
  ser2net                               # a real RFC 2217 terminal server in front of `sabus sim --pty` (tests/tools)
  python3-serial                        # pyserial's rfc2217:// client against `sabus sim --rfc2217` (/usr/bin/python3)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
