#!/usr/bin/env bash
# The shipped cold deck runs, converges and writes the layout of docs/model.md "Results" with finite numbers.
set -eu
solve=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$solve" inputs/crf450r_4000rpm_full_cold.nml -o "$tmp/cold.h5" | tee "$tmp/out.txt"
grep -Eq 'energy loss per cycle +[0-9]+\.[0-9]+ J' "$tmp/out.txt"
for a in energy_loss_J mixed_share_pct ring_mass_g min_film_m max_friction_N converged cycles_run deck; do
  h5dump -a "$a" "$tmp/cold.h5" > /dev/null
done
for d in crank_angle_deg sliding_speed_m_s h0_m lambda_min gas_pressure_Pa applied_load_N \
         hydrodynamic_load_N asperity_load_N viscous_friction_N boundary_friction_N friction_N power_loss_W; do
  h5dump -a "/cycle/$d/units" "$tmp/cold.h5" > /dev/null
done
! h5dump "$tmp/cold.h5" | grep -Eiq 'nan|inf'
# crank_angle_deg is the dimension scale of /cycle (its coordinate for netCDF/xarray)
h5dump -a /cycle/crank_angle_deg/CLASS "$tmp/cold.h5" | grep -q '"DIMENSION_SCALE"'
h5dump -a /cycle/h0_m/DIMENSION_LIST "$tmp/cold.h5" > /dev/null

# a deck over 64 KiB (the limit of an attribute kept in the object header) keeps its
# `deck` attribute whole (dense attribute storage): here 100 KiB of comments
cp -r inputs/pressure inputs/calibration.nml "$tmp/"
cp inputs/crf450r_4000rpm_full_cold.nml "$tmp/big.nml"
for i in $(seq 1 1400); do
  printf '! comment line %05d to make the deck larger than 64 KiB: ..................\n' "$i"
done >> "$tmp/big.nml"
size=$(wc -c < "$tmp/big.nml")
[ "$size" -gt 102400 ]
"$solve" -q "$tmp/big.nml" -o "$tmp/big.h5"
h5dump -a deck "$tmp/big.h5" | grep -q 'comment line 01400 to make the deck'
h5dump -a deck "$tmp/big.h5" | grep -q 'calibration file'
echo "2 passed, 0 failed"
