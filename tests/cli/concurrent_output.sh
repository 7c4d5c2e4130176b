#!/usr/bin/env bash
# Two ringlube-solve runs writing the same -o at the same time: each
# writes a uniquely named temporary file and renames it into place, so for every pair
# both runs exit 0, the final file is complete and equals the result of one of the two
# runs (byte for byte in h5dump, run time aside), and no temporary file is left.
# Usage: concurrent_output.sh RINGLUBE_SOLVE [PAIRS]   (default 40 pairs)
set -u
case $1 in */*) solve=$(realpath "$1");; *) solve=$1;; esac
pairs=${2:-40}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r inputs/pressure "$tmp/"
cd "$tmp"
cat > a.nml <<'NML'
&operating speed_rpm = 4000, pressure_file = 'pressure/crf450r_4000rpm_full.csv' /
&ring width = 1.004e-3, crown_height = 9.31e-6 /
&numerics nodes = 31, dpsi_deg = 5 /
NML
sed 's/width = 1.004e-3/width = 1.2e-3/' a.nml > b.nml

# h5dump of a result without its file name, the output.file it records and its run time
# (the only parts that differ between two runs of the same deck)
dump() {
  h5dump "$1" | tail -n +2 | awk '/ATTRIBUTE "(run_time_s|output.file)"/ {skip = 1} skip && /^   }$/ {skip = 0; next} !skip'
}
"$solve" -q a.nml -o ref_a.h5 && "$solve" -q b.nml -o ref_b.h5 || { echo "FAIL reference runs"; exit 1; }
dump ref_a.h5 > ref_a.txt
dump ref_b.h5 > ref_b.txt
if cmp -s ref_a.txt ref_b.txt; then echo "FAIL the two decks give the same result"; exit 1; fi
grep -q 'GROUP "cycle"' ref_a.txt && grep -q 'ATTRIBUTE "deck"' ref_a.txt || { echo "FAIL reference layout"; exit 1; }

fail=0; won_a=0; won_b=0
for i in $(seq 1 "$pairs"); do
  rm -f out.h5
  "$solve" -q a.nml -o out.h5 2> err_a & pa=$!
  "$solve" -q b.nml -o out.h5 2> err_b & pb=$!
  wait $pa; ra=$?
  wait $pb; rb=$?
  if [ $ra -ne 0 ] || [ $rb -ne 0 ]; then
    echo "FAIL pair $i: exit $ra and $rb"; cat err_a err_b; fail=$((fail+1)); continue
  fi
  dump out.h5 > out.txt 2>&1
  if cmp -s out.txt ref_a.txt; then won_a=$((won_a+1))
  elif cmp -s out.txt ref_b.txt; then won_b=$((won_b+1))
  else echo "FAIL pair $i: the final file is neither run's result"; head -5 out.txt; fail=$((fail+1))
  fi
  if ls ./*.part > /dev/null 2>&1; then echo "FAIL pair $i: temporary file left: $(ls ./*.part)"; fail=$((fail+1)); rm -f ./*.part; fi
done
echo "$pairs pairs: final file from run a $won_a times, from run b $won_b times, $fail failures"
[ $fail -eq 0 ]
