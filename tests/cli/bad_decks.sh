#!/usr/bin/env bash
# Bad decks: each must exit with status 2, name the file, group and variable (or line),
# and leave no result file behind (neither the output nor a temporary `out.h5.*.part`).
# Unsafe outputs (an input of the run, a folder, a device, a missing folder) exit 2 and
# leave every file as it was; a write that fails (file-size limit, as a full disk) exits 1
# and leaves no temporary file. A non-converged run exits 3 and still writes its file.
set -u
case $1 in */*) solve=$(realpath "$1");; *) solve=$1;; esac   # some cases run in another folder
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
leftovers() {  # prints and succeeds if an output or a temporary output file exists
  (cd "$tmp" && ls -d out.h5* 2>/dev/null) | grep . && return 0; return 1
}
expect_error() {  # name, expected-regex, deck text
  local name=$1 regex=$2
  printf '%s\n' "$3" > "$tmp/$name.nml"
  rm -f "$tmp"/out.h5*
  "$solve" "$tmp/$name.nml" > "$tmp/stdout" 2> "$tmp/stderr"
  local rc=$?
  if [ $rc -ne 2 ]; then echo "FAIL $name: exit $rc, expected 2"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if ! grep -Eq -- "$regex" "$tmp/stderr"; then echo "FAIL $name: message does not match /$regex/:"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if ! grep -q "$name.nml" "$tmp/stderr"; then echo "FAIL $name: message does not name the file"; fail=$((fail+1)); return; fi
  if leftovers; then echo "FAIL $name: a result file was left behind: $(leftovers)"; fail=$((fail+1)); return; fi
  echo "ok   $name: $(cat "$tmp/stderr")"; pass=$((pass+1))
}
base="&output file = 'out.h5' /
&operating pressure_file = 'pressure/crf450r_4000rpm_full.csv' /"
expect_error unknown_variable '&ring widht: unknown variable' "$base
&ring widht = 1e-3 /"
expect_error unknown_group 'unknown namelist group &rings' "$base
&rings width = 1e-3 /"
expect_error list_for_a_scalar 'list_for_a_scalar.nml:4: &ring width: malformed value "1e-3 1.2e-3" \(one value per variable\)' "$base
&ring crown_height = 9.31e-6,
  width = 1e-3, 1.2e-3 /"
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
# the ring-pack gas network is not yet coupled to the film: refused, not ignored
expect_error ring_pack_range '&ring_pack gamma: must be in' "$base
&ring_pack gamma = 0.9 /"
expect_error twice '&ring width: given twice' "$base
&ring width = 1e-3, width = 2e-3 /"
expect_error missing_pressure_file '&operating pressure_file: .*nothere.csv: pressure file not found' "&output file = 'out.h5' /
&operating pressure_file = 'nothere.csv' /"
printf '# header comment\ncrank_angle_deg,pressure_Pa\n0,1e5\n10,1.1e5\n20;1.2e5\n720,1e5\n' > "$tmp/badrow.csv"
expect_error csv_bad_row 'badrow.csv: line 5: expected "crank angle deg, pressure Pa"' "&output file = 'out.h5' /
&operating pressure_file = 'badrow.csv' /"
# a first row that is a number or nan/inf is data, never a header
for row in 'nan,1e5' 'inf,1e5' '-Infinity,1e5' 'NaN,1e5'; do
  printf '%s\n10,1.1e5\n720,1e5\n' "$row" > "$tmp/nan_first.csv"
  expect_error "csv_first_row_${row//[^a-zA-Z]/_}" 'nan_first.csv: line 1: crank angle is not a finite number' \
    "&output file = 'out.h5' /
&operating pressure_file = 'nan_first.csv' /"
done
printf 'crank_angle_deg,pressure_Pa\n0,1e5\n10,nan\n720,1e5\n' > "$tmp/nan_row.csv"
expect_error csv_nan_pressure 'nan_row.csv: line 3: pressure is not a finite number: "10,nan"' "&output file = 'out.h5' /
&operating pressure_file = 'nan_row.csv' /"
printf '0,1e5\n10,1e999\n720,1e5\n' > "$tmp/overflow.csv"
expect_error csv_overflow 'overflow.csv: line 2: pressure is not a finite number' "&output file = 'out.h5' /
&operating pressure_file = 'overflow.csv' /"
printf 'angle,1e5\n10,1.1e5\n720,1e5\n' > "$tmp/half_header.csv"
expect_error csv_half_header 'half_header.csv: line 1: expected "crank angle deg, pressure Pa"' "&output file = 'out.h5' /
&operating pressure_file = 'half_header.csv' /"

# unsafe outputs: refused before the run (exit 2), every input left as it was
printf '! calibration\n&ring tension = 8.0 /\n' > "$tmp/calib.nml"
sed "s|^&output.*|\&calibration file = 'calib.nml' /|; s|^&ring.*|\&ring width = 1.004e-3 /|" "$good" > "$tmp/withcal.nml"
ln -sf withcal.nml "$tmp/link.nml"
ln -f "$tmp/calib.nml" "$tmp/hardlink.nml"
mkdir -p "$tmp/folder"
sums() { (cd "$tmp" && cat withcal.nml calib.nml pressure/crf450r_4000rpm_full.csv | cksum); }
before=$(sums)
expect_refused() {  # name, expected-regex, -o value
  local name=$1 regex=$2 out=$3
  rm -f "$tmp"/out.h5*
  (cd "$tmp" && "$solve" -q withcal.nml -o "$out") > "$tmp/stdout" 2> "$tmp/stderr"
  local rc=$?
  if [ $rc -ne 2 ]; then echo "FAIL $name: exit $rc, expected 2"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if ! grep -Eq -- "$regex" "$tmp/stderr"; then echo "FAIL $name: message does not match /$regex/:"; cat "$tmp/stderr"; fail=$((fail+1)); return; fi
  if [ "$(sums)" != "$before" ]; then echo "FAIL $name: an input was changed"; fail=$((fail+1)); return; fi
  if ls "$tmp"/*.part "$tmp"/*/*.part > /dev/null 2>&1; then echo "FAIL $name: a temporary file was left behind"; fail=$((fail+1)); return; fi
  echo "ok   $name: $(cat "$tmp/stderr")"; pass=$((pass+1))
}
expect_refused out_is_deck '^ringlube-solve: error: withcal.nml: output is the deck withcal.nml of this run' withcal.nml
expect_refused out_is_deck_spelt './withcal.nml: output is the deck' ./withcal.nml
# (a symbolic link is refused as such, whatever it points to: the rule of every ringlube writer)
expect_refused out_is_deck_symlink 'link.nml: output is a symbolic link' link.nml
expect_refused out_is_pressure 'folder/../pressure/crf450r_4000rpm_full.csv: output is the pressure file' folder/../pressure/crf450r_4000rpm_full.csv
expect_refused out_is_calibration 'calib.nml: output is the calibration file' calib.nml
expect_refused out_is_calibration_hardlink 'hardlink.nml: output is the calibration file' hardlink.nml
expect_refused out_is_folder 'folder: output is a folder, not a file' folder
expect_refused out_is_folder_slash 'folder/: output names a folder, not a file' folder/
expect_refused out_is_device '/dev/null: output exists and is not a regular file' /dev/null
expect_refused out_folder_missing 'nothere/out.h5: output folder nothere does not exist' nothere/out.h5
expect_refused out_empty 'the output file name is empty' ''
if [ -c /dev/null ]; then echo "ok   dev_null_still_a_device"; pass=$((pass+1)); else echo "FAIL /dev/null was replaced"; fail=$((fail+1)); fi

# a write that fails (here the file-size limit; a full disk is the same error path), at
# several points of the writing (a ~31 KiB result: limits in KiB, the last fails when the
# file is closed): exit 1, the system's message, no temporary file, an earlier result
# left untouched, no crash
for lim in 1 8 16 24 31; do
  rm -f "$tmp"/out.h5*
  printf 'old result\n' > "$tmp/out.h5"
  (ulimit -f $lim; "$solve" -q "$good") > "$tmp/stdout" 2> "$tmp/stderr"; rc=$?
  if [ $rc -eq 1 ] && grep -q 'out.h5: cannot write the result.*File too large' "$tmp/stderr" \
     && [ "$(cat "$tmp/out.h5")" = "old result" ] && ! ls "$tmp"/out.h5.*.part > /dev/null 2>&1; then
    echo "ok   file_size_limit_${lim}k: $(cat "$tmp/stderr")"; pass=$((pass+1))
  else
    echo "FAIL file_size_limit_${lim}k: exit $rc"; cat "$tmp/stderr"; ls "$tmp"; fail=$((fail+1))
  fi
done
rm -f "$tmp"/out.h5*

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
