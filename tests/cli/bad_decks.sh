#!/usr/bin/env bash
# Bad decks: each must exit with status 2, name the file, group and variable (or line),
# and leave no result file behind. A non-converged run exits 3 and still writes its file.
set -u
solve=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r inputs/pressure "$tmp/"
good="$tmp/good.nml"
cat > "$good" <<'NML'
&operating speed_rpm = 4000, pressure_file = 'pressure/crf450r_4000rpm_full.csv' /
&ring width = 1.004e-3, crown_height = 9.31e-6 /
&numerics nodes = 31, dpsi_deg = 5 /
&output file = 'out.h5' /
NML
fail=0; pass=0
expect_error() {  # name, expected-regex, deck text
  local name=$1 regex=$2
  printf '%s\n' "$3" > "$tmp/$name.nml"
  rm -f "$tmp/out.h5" "$tmp/out.h5.part"
  "$solve" "$tmp/$name.nml" > "$tmp/stdout" 2> "$tmp/stderr"
  local rc=$?
  if [ $rc -ne 2 ]; then echo "FAIL $name: exit $rc, expected 2"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if ! grep -Eq -- "$regex" "$tmp/stderr"; then echo "FAIL $name: message does not match /$regex/:"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if ! grep -q "$name.nml" "$tmp/stderr"; then echo "FAIL $name: message does not name the file"; fail=$((fail+1)); return; fi
  if [ -e "$tmp/out.h5" ] || [ -e "$tmp/out.h5.part" ]; then echo "FAIL $name: a result file was left behind"; fail=$((fail+1)); return; fi
  echo "ok   $name: $(cat "$tmp/stderr")"; pass=$((pass+1))
}
base="&output file = 'out.h5' /
&operating pressure_file = 'pressure/crf450r_4000rpm_full.csv' /"
expect_error unknown_variable '&ring widht: unknown variable' "$base
&ring widht = 1e-3 /"
expect_error unknown_group 'unknown namelist group &rings' "$base
&rings width = 1e-3 /"
expect_error malformed_number '&ring width: malformed number "1.0.0e-3"' "$base
&ring width = 1.0.0e-3 /"
expect_error malformed_word '&ring tension: malformed number "eight"' "$base
&ring tension = eight /"
expect_error reads_as_eof '&ring \(opened on line 3\) is not closed' "$base
&ring width = 1e-3, tension = 8"
expect_error two_values '&ring width: malformed value "1e-3 2e-3"' "$base
&ring width = 1e-3 2e-3 /"
expect_error missing_value '&ring tension: missing value' "$base
&ring width = 1e-3, tension = /"
expect_error malformed_logical '&physics squeeze: malformed logical "yes"' "$base
&physics squeeze = yes /"
expect_error malformed_integer '&numerics nodes: malformed integer "2.5"' "$base
&numerics nodes = 2.5 /"
expect_error negative_width '&ring width: must be in \[1.0E-5, 5.0E-2\] m, got -1.0E-3' "$base
&ring width = -1e-3 /"
expect_error bad_option "&physics outlet: must be 'reynolds' or 'ambient'" "$base
&physics outlet = 'sommerfeld' /"
expect_error twice '&ring width: given twice' "$base
&ring width = 1e-3, width = 2e-3 /"
expect_error missing_pressure_file '&operating pressure_file: .*nothere.csv: pressure file not found' "&output file = 'out.h5' /
&operating pressure_file = 'nothere.csv' /"
printf '# header comment\ncrank_angle_deg,pressure_Pa\n0,1e5\n10,1.1e5\n20;1.2e5\n720,1e5\n' > "$tmp/badrow.csv"
expect_error csv_bad_row 'badrow.csv: line 5: expected "crank angle deg, pressure Pa"' "&output file = 'out.h5' /
&operating pressure_file = 'badrow.csv' /"

# a run that cannot become periodic in one cycle: exit 3, file written with converged = 0
sed 's/dpsi_deg = 5 \//dpsi_deg = 5, max_cycles = 1, warmup_deg = 0, cycle_tol = 1e-12 \//' "$good" > "$tmp/noconv.nml"
"$solve" -q "$tmp/noconv.nml" 2> "$tmp/stderr"; rc=$?
if [ $rc -eq 3 ] && [ -s "$tmp/out.h5" ] && h5dump -a converged "$tmp/out.h5" | grep -q '(0): 0'; then
  echo "ok   not_converged: exit 3, file written with converged = 0"; pass=$((pass+1))
else
  echo "FAIL not_converged: exit $rc"; cat "$tmp/stderr"; fail=$((fail+1))
fi
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
