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
