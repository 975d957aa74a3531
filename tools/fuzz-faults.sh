#!/usr/bin/env bash
# How many of the reference controller's faults the live fuzzer finds over a
# pty (issue 24), and whether it stays quiet on clean controllers. Printed,
# not asserted (timing-dependent: a measurement, not a test).
#
# For each fault (`sabus sim --list-faults`, or the ones named): `sabus sim
# --pty --fault NAME` with the profile the fault shows on (the table below;
# rc3000-1.59 otherwise) and `sabus fuzz --port ... --pace 0 --max-time S
# --allow-motion --allow-destructive --fresh-device` (a sim is a controller
# just powered on); prints found (the first finding's kind,
# seconds and writes to it) or missed, and the total. Then a clean run per
# shipped profile and per random legal profile (sabus vectors sweep's
# generator, --random N): 0 findings expected; a clean run's finding is kept
# (its vector, the fuzzer's output, the sim's transcript, the profile) in a
# new directory whose name is printed.
#
#   tools/fuzz-faults.sh [--max-time S] [--seed N] [--random N] [--no-faults] [--no-clean] [FAULT[@PROFILE] ...]
set -euo pipefail
cd "$(dirname "$0")/.."
sabus=${SABUS:-$PWD/build/tools/sabus}  # SABUS: another build of it
[[ -x $sabus ]] || { echo "build first: $sabus" >&2; exit 2; }

max_time=60 seed=1 random=0 faults_on=1 clean_on=1
names=()
while (($#)); do
  case $1 in
    --max-time) max_time=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --random) random=$2; shift 2 ;;
    --no-faults) faults_on=0; shift ;;
    --no-clean) clean_on=0; shift ;;
    -h|--help) sed -n 2,14p "$0"; exit 0 ;;
    *) names+=("$1"); shift ;;
  esac
done

# The profile a fault needs to be visible at all (a switch of the profile
# the fault's rule rests on), or to be reached within a minute (a limit, a
# LOCATE's geometry: the fast mount's 20 deg/s); every other fault runs on
# rc3000-1.59.
profile_for() {
  case $1 in
    circular-pol-acked|stow-without-capability) echo circular-no-stow ;;
    remote-disabled-answers|offline-without-f) echo remote-disabled ;;
    pulse-count-stale|pulse-count-no-offset|form2b-negative-mirrored) echo pulse-counts ;;
    hundredths-always-zero|form2c-sign-dropped|locate-northern-latitude) echo southern-slow-mount ;;
    # A site without latitude and longitude: a LOCATE waits for them (E-59).
    locate-without-site-completes) echo dual-port-dvb-fluxgate ;;
    # A pot-sensed azimuth whose 0.0 is not true north (heading 90).
    locate-ignores-heading|locate-azimuth-counterclockwise|locate-eastern-longitude|az-limit-bits-missing|jog-into-limit-acked)
      echo fast-mount-manual-nav ;;
    # An axis alarm to reset (§3.7 'R').
    drive-reset-keeps-alarm) echo az-jammed ;;
    *) echo rc3000-1.59 ;;
  esac
}

work=$(mktemp -d /tmp/sabus-fuzz-faults.XXXXXX)
sim_pid=
cleanup() {
  [[ -n $sim_pid ]] && kill -INT "$sim_pid" 2>/dev/null && wait "$sim_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT

# One session: sim with PROFILE and FAULT (may be empty), fuzz over its pty.
# Prints the fuzzer's first FINDING line (or nothing) and the writes line.
session() {
  local profile=$1 fault=$2 link="$work/pty" out="$work/fuzz.out"
  local args=(sim --pty --link "$link" --profile "$profile" --log "$work/sim.log")
  [[ -n $fault ]] && args+=(--fault "$fault")
  rm -rf "$work/findings" "$link" "$work/sim.log"
  "$sabus" "${args[@]}" >"$work/sim.out" 2>&1 &
  sim_pid=$!
  for _ in $(seq 100); do grep -q READY "$work/sim.out" 2>/dev/null && break; sleep 0.05; done
  local t0; t0=$(date +%s.%N)
  "$sabus" fuzz --port "$link" --pace 0 --max-time "$max_time" --seed "$seed" --max-findings 1 \
    --allow-motion --allow-destructive --fresh-device --profile "$profile" --findings "$work/findings" >"$out" 2>&1 || true
  kill -INT "$sim_pid" 2>/dev/null || true
  wait "$sim_pid" 2>/dev/null || true
  sim_pid=
  grep -m1 '^FINDING' "$out" || true
  grep -m1 -E '^[0-9]+ writes' "$out" || true
}

if ((faults_on)); then
  if ((${#names[@]} == 0)); then
    mapfile -t names < <("$sabus" sim --list-faults | awk '{print $1}')
  fi
  found=0 total=0
  echo "faults over a pty, ${max_time} s each, seed $seed:"
  for entry in "${names[@]}"; do
    fault=${entry%%@*}
    profile=$(profile_for "$fault")
    [[ $entry == *@* ]] && profile=${entry#*@}
    result=$(session "vectors/profiles/$profile.yaml" "$fault")
    total=$((total + 1))
    # FINDING KIND after N writes, T s: ...
    if [[ $result =~ FINDING\ ([a-z-]+)\ after\ ([0-9]+)\ writes,\ ([0-9.]+)\ s ]]; then
      found=$((found + 1))
      printf '  %-34s found    %-24s %7s s  %7s writes  (%s)\n' "$fault" "${BASH_REMATCH[1]}" "${BASH_REMATCH[3]}" \
        "${BASH_REMATCH[2]}" "$profile"
    else
      writes=$(grep -oE '^[0-9]+ writes' <<<"$result" || echo "? writes")
      printf '  %-34s MISSED   %-24s %9s  %7s  (%s)\n' "$fault" "" "" "${writes% writes} writes" "$profile"
    fi
  done
  echo "found $found of $total faults"
fi

# A clean run's finding is a false alarm to chase: its vector, the fuzzer's
# output, the sim's transcript and the profile go to a new directory of
# their own (printed), which the clean-up leaves.
clean_result() {
  local profile=$1 result=$2
  if [[ $result != *FINDING* ]]; then
    echo "0 findings, $(grep -oE '^[0-9]+ writes' <<<"$result")"
    return
  fi
  # A directory of its own, never one that exists (mktemp), so nothing is
  # replaced; what is not there to keep (no vector written, say) is named.
  local kept missing=() item
  kept=$(mktemp -d /tmp/sabus-clean-finding.XXXXXX)
  for item in "$work/findings" "$work/fuzz.out" "$work/sim.log" "$profile"; do
    cp -r "$item" "$kept/" 2>/dev/null || missing+=("$(basename "$item")")
  done
  echo "FINDING: ${result%%$'\n'*} (kept in $kept${missing[*]:+; not kept: ${missing[*]}})"
}

if ((clean_on)); then
  echo "clean controllers over a pty, ${max_time} s each (0 findings expected):"
  for p in vectors/profiles/*.yaml; do
    result=$(session "$p" "")
    printf '  %-40s %s\n' "$(basename "$p" .yaml)" "$(clean_result "$p" "$result")"
  done
  if ((random > 0)); then
    # The sweep's generator (harness/profile profile_generator): its profiles
    # written out by a sweep of N profiles with the same seed.
    "$sabus" vectors sweep --profiles "$random" --seed "$seed" --write-profiles "$work/random" >/dev/null 2>&1 || true
    for f in "$work"/random/*.yaml; do
      [[ -f $f ]] || continue
      result=$(session "$f" "")
      printf '  %-40s %s\n' "$(basename "$f" .yaml)" "$(clean_result "$f" "$result")"
    done
  fi
fi
