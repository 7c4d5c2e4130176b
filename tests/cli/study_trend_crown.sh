#!/usr/bin/env bash
# Expected failure (ctest WILL_FAIL, label `known_limitation`): the source study reports that
# the energy loss FALLS as the crown height rises (docs/validation.md, "Published trends");
# ringlube, with the calibrated lumped contact area, gives the opposite trend. This script
# checks the study's trend on the shipped cold deck at crown heights 8 and 13 um (the other
# inputs as shipped) and fails while ringlube does not reproduce it.
#
# ctest inverts the result of a WILL_FAIL test, so this script exits 1 only for the one
# expected outcome (both runs fine, trend absent) and 0 for everything else: a failed run,
# an unreadable summary, or the trend present. ctest then reports those as failures, and
# the last one means the limitation is gone: remove WILL_FAIL and make this a plain test.
set -u -o pipefail
solve=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r inputs/pressure inputs/calibration.nml "$tmp/"

energy() { # crown height in m -> energy loss in J on stdout
  sed "s/crown_height = 9.31e-6/crown_height = $1/" inputs/crf450r_4000rpm_full_cold.nml \
    > "$tmp/crown.nml"
  grep -q "crown_height = $1" "$tmp/crown.nml" || { echo "deck edit failed" >&2; return 1; }
  "$solve" "$tmp/crown.nml" -o "$tmp/crown.h5" \
    | sed -nE 's/^ *energy loss per cycle +([0-9.]+) J$/\1/p' | grep .
}

low=$(energy 8e-6) || { echo "UNEXPECTED: the run at crown height 8 um failed"; exit 0; }
high=$(energy 13e-6) || { echo "UNEXPECTED: the run at crown height 13 um failed"; exit 0; }
echo "energy loss: crown 8 um $low J, crown 13 um $high J"
if awk -v a="$low" -v b="$high" 'BEGIN { exit !(b < a) }'; then
  echo "UNEXPECTED PASS: energy falls with crown height as the study reports;" \
    "the limitation is gone, remove WILL_FAIL from study_trend_crown_height"
  exit 0
fi
echo "known limitation: energy rises with crown height (the study reports it falls)"
exit 1
