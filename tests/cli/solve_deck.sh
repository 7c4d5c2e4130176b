#!/usr/bin/env bash
# The shipped cold deck runs, converges and writes the SPEC layout with finite numbers.
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
echo "1 passed, 0 failed"
