#!/usr/bin/env bash
# gate.sweep (issue 22): the suite on random legal profiles, three times: the
# fixed seed 1, which every run repeats, a fresh seed drawn for this run, so
# that CI keeps exploring profiles nobody tuned on, and a fresh seed against
# the controller that takes the other side of every open point. Each sweep prints its
# seed first; a failing profile is written to OUT with its seed (reproduce:
# sabus vectors sweep --profile-seed SEED). Both run; either failing fails.
# The third only with a fourth argument, OTHER (the release build's: the
# sanitizer build proves the other readings in its unit tests).
#   sweep_gate.sh SABUS OUT PROFILES [OTHER]
set -u
sabus="$1" out="$2" profiles="$3" other="${4:-}"
status=0
"$sabus" vectors sweep --profiles "$profiles" --seed 1 --out "$out" || status=1
"$sabus" vectors sweep --profiles "$profiles" --seed fresh --out "$out" || status=1
# A controller on the other side of every open point of the spec (readings.hpp;
# issue 31), on fresh profiles: a legal controller never fails.
if [[ $other == OTHER ]]; then
  "$sabus" vectors sweep --profiles "$profiles" --seed fresh --reading other --out "$out" || status=1
fi
exit "$status"
