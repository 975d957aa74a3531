#!/usr/bin/env bash
# gate.sweep (issue 22): the suite on random legal profiles: the fixed seed
# 1, which every run repeats; a fresh seed drawn for this run, so that CI
# keeps exploring profiles nobody tuned on; and two more fresh seeds against
# the controller that takes the other side of every open point, then the
# third side where an entry lists one (other-2). Each sweep prints its seed
# first; a failing profile is written to OUT with its seed (reproduce:
# sabus vectors sweep --profile-seed SEED). All run; any failing fails.
# The last two only with a fourth argument, OTHER (the release build's: the
# sanitizer build proves the other readings in its unit tests).
#   sweep_gate.sh SABUS OUT PROFILES [OTHER]
set -u
sabus="$1" out="$2" profiles="$3" other="${4:-}"
status=0
"$sabus" vectors sweep --profiles "$profiles" --seed 1 --out "$out" || status=1
"$sabus" vectors sweep --profiles "$profiles" --seed fresh --out "$out" || status=1
# A controller on the other side of every open point of the spec (readings.hpp;
# issue 31), on fresh profiles: a legal controller never fails.
# And on the third side of every entry that lists one (other-2; other
# elsewhere).
if [[ $other == OTHER ]]; then
  "$sabus" vectors sweep --profiles "$profiles" --seed fresh --reading other --out "$out" || status=1
  "$sabus" vectors sweep --profiles "$profiles" --seed fresh --reading other-2 --out "$out" || status=1
fi
exit "$status"
