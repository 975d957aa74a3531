#!/usr/bin/env bash
# gate.sweep (issue 22): the suite on random legal profiles, twice: the fixed
# seed 1, which every run repeats, and a fresh seed drawn for this run, so
# that CI keeps exploring profiles nobody tuned on. Each sweep prints its
# seed first; a failing profile is written to OUT with its seed (reproduce:
# sabus vectors sweep --profile-seed SEED). Both run; either failing fails.
#   sweep_gate.sh SABUS OUT PROFILES
set -u
sabus="$1" out="$2" profiles="$3"
status=0
"$sabus" vectors sweep --profiles "$profiles" --seed 1 --out "$out" || status=1
"$sabus" vectors sweep --profiles "$profiles" --seed fresh --out "$out" || status=1
exit "$status"
