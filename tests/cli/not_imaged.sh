#!/usr/bin/env bash
# A field a model cannot image (no chief ray reaches the sensor) does not cost the table:
# lens-spot and lens-distort print every row, that field's as nan, warn naming it, and
# exit 2 (lens-spot(1), lens-distort(1): EXIT STATUS); the other rows are those of a run
# without that field.
source "$(dirname "$0")/lib.sh"

# the flat window passes nothing at 89 degrees; the perfect system beside it does
run $BIN/lens-spot tests/data/window.lens --compare tests/data/perfect-50mm.poly --fields 0,30,89 \
  --rays 20 --wavelengths d >$T/spot.txt 2>$T/err.txt; rc=$?
run $BIN/lens-spot tests/data/window.lens --compare tests/data/perfect-50mm.poly --fields 0,30 \
  --rays 20 --wavelengths d >$T/spot2.txt 2>/dev/null
if [ $rc -eq 2 ] && [ "$(awk '$1 == "lens" && $2 == 89 { print $4, $5, $6, $11 }' $T/spot.txt)" = "0 0 nan nan" ] &&
   near "$(awk '$1 == "poly" && $2 == 89 { print $8 }' $T/spot.txt)" "$(awk 'BEGIN { printf "%.10f", 50 * sin(89 * atan2(1, 1) / 45) }')" 1e-6 &&
   [ "$(grep -c . $T/err.txt)" = 1 ] && grep -q "^lens-spot: warning: lens: field 89 deg: .*; its rows are nan$" $T/err.txt &&
   diff <(grep -v '^[a-z]* 89 ' $T/spot.txt) $T/spot2.txt >/dev/null
then ok spot_field_not_imaged; else fail spot_field_not_imaged "rc=$rc $(cat $T/err.txt) $(cat $T/spot.txt)"; fi

# the issue's case: a system fitted to fisheye-ii cannot image 98.53 degrees
# (without passage columns: a system with inner-rim circles images no field of fisheye-ii
# through imaging.c's chief-ray solve at present)
run $BIN/lens-trace lenses/fisheye-ii.lens -n 2000 --seed 1 --no-passage-columns |
  run $BIN/lens-fit -q --terms 20 -o $T/fe.poly 2>/dev/null
run $BIN/lens-distort lenses/fisheye-ii.lens --compare $T/fe.poly --fields 0,49.27,98.53 --illum-rays 0 \
  --grid 2 >$T/d.txt 2>$T/err.txt; rc=$?
if [ $rc -eq 2 ] && [ "$(awk '$1 == "poly" && $2 == 98.53 { print $3, $5 }' $T/d.txt)" = "nan nan" ] &&
   awk '$1 == "lens" && $2 == 98.53 && $3 > 13.9 && $3 < 14 { ok = 1 } END { exit !ok }' $T/d.txt &&
   grep -q '^# best mapping (poly): equisolid' $T/d.txt &&
   grep -q "^lens-distort: warning: poly: field 98.53 deg: .*; its row is nan$" $T/err.txt
then ok distort_field_not_imaged; else fail distort_field_not_imaged "rc=$rc $(cat $T/err.txt) $(cat $T/d.txt)"; fi

# the designer commands alike (lens-fan(1), lens-field(1), lens-mtf(1), lens-layout(1):
# EXIT STATUS): the system's rows of 98.53 degrees nan, the lens's computed, one warning,
# status 2, every other row as in a run without that field
F3=0,49.27,98.53
for c in fan:6 field:4 mtf:5; do
  k=${c#*:} c=${c%:*} # k: the first figure's column (after model, field, wavelength, fan and pupil or frequency)
  run $BIN/lens-$c lenses/fisheye-ii.lens --compare $T/fe.poly --fields $F3 --wavelengths d \
    --png $T/$c.png >$T/$c.txt 2>$T/err.txt; rc=$?
  run $BIN/lens-$c lenses/fisheye-ii.lens --compare $T/fe.poly --fields 0,49.27 --wavelengths d \
    >$T/${c}2.txt 2>/dev/null
  # the figures: nan on every poly row of the field, numbers on the lens's
  if [ $rc -eq 2 ] &&
     awk -v k=$k '!/^#/ && $2 == 98.53 { for (i = k; i <= NF; i++) {
            if ($1 == "poly") { n++; bad += $i != "nan" } else if ($i != "nan") lens = 1 } }
          END { exit !(n > 0 && lens && !bad) }' $T/$c.txt &&
     [ "$(grep -c . $T/err.txt)" = 1 ] &&
     grep -q "^lens-$c: warning: poly: field 98.53 deg: no chief ray .*; its rows are nan$" $T/err.txt &&
     diff <(grep -v '^#' $T/$c.txt | grep -v '^[a-z]* 98.53 ') <(grep -v '^#' $T/${c}2.txt) >/dev/null &&
     [ "$(head -c 4 $T/$c.png 2>/dev/null | od -An -tx1 | tr -d ' ')" = 89504e47 ]
  then ok ${c}_field_not_imaged; else fail ${c}_field_not_imaged "rc=$rc $(cat $T/err.txt) $(head -5 $T/$c.txt)"; fi
done

# the differences are over the fields both models image: those of the run without 98.53
for c in fan field mtf; do
  a=$(grep '^# poly - lens' $T/$c.txt | sed 's/ (.*left out)//') b=$(grep '^# poly - lens' $T/${c}2.txt | sed 's/ (.*left out)//')
  if [ -n "$a" ] && [ "$a" = "$b" ]; then ok ${c}_difference_not_imaged; else fail ${c}_difference_not_imaged "'$a' vs '$b'"; fi
done

# JSON: nan as null, the warning in "warnings"
run $BIN/lens-field lenses/fisheye-ii.lens --compare $T/fe.poly --fields $F3 --wavelengths d --json \
  >$T/f.json 2>/dev/null; rc=$?
if [ $rc -eq 2 ] && python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
poly = [r for r in d["field_curves"] if r["model"] == "poly" and r["field_deg"] == 98.53]
assert poly and all(r["z_tan_mm"] is None and r["chief_y_mm"] is None for r in poly)
assert len(d["warnings"]) == 1 and d["warnings"][0].startswith("poly: field 98.53 deg: ")
' $T/f.json 2>$T/err.txt
then ok field_json_not_imaged; else fail field_json_not_imaged "rc=$rc $(cat $T/err.txt)"; fi

# lens-layout: the system's rays of that field are not drawn (no more dotted lines than
# without it), the lens's are
run $BIN/lens-layout lenses/fisheye-ii.lens --compare $T/fe.poly --fields 0,98.53 --rays 5 \
  --svg $T/l.svg >/dev/null 2>$T/err.txt; rc=$?
run $BIN/lens-layout lenses/fisheye-ii.lens --compare $T/fe.poly --fields 0 --rays 5 --svg $T/l0.svg \
  >/dev/null 2>/dev/null
if [ $rc -eq 2 ] && [ "$(grep -c 'dasharray="1 1"' $T/l.svg)" = "$(grep -c 'dasharray="1 1"' $T/l0.svg)" ] &&
   [ "$(grep -c '<polyline fill="none" stroke="#009933"' $T/l.svg)" -gt 0 ] &&
   [ "$(grep -c . $T/err.txt)" = 1 ] &&
   grep -q '^lens-layout: warning: poly: field 98.53 deg: .*; its rays are not drawn$' $T/err.txt
then ok layout_field_not_imaged; else fail layout_field_not_imaged "rc=$rc $(cat $T/err.txt)"; fi

# a field the lens itself cannot image, named outright, as lens-spot has it: nan rows, status 2
run $BIN/lens-fan lenses/dgauss.50mm.lens --fields 0,80 --wavelengths d >$T/f.txt 2>$T/err.txt; rc=$?
if [ $rc -eq 2 ] && [ "$(awk '!/^#/ && $2 == 80 && ($6 != "nan" || $7 != "nan")' $T/f.txt | wc -l)" = 0 ] &&
   [ "$(awk '!/^#/ && $2 == 80' $T/f.txt | wc -l)" -gt 0 ] &&
   awk '!/^#/ && $2 == 0 && $6 != "nan" { ok = 1 } END { exit !ok }' $T/f.txt &&
   grep -q '^lens-fan: warning: lens: field 80 deg: no chief ray .*; its rows are nan$' $T/err.txt
then ok fan_lens_field_not_imaged; else fail fan_lens_field_not_imaged "rc=$rc $(cat $T/err.txt)"; fi
