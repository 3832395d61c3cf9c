#!/usr/bin/env bash
# A design file's fields, wavelengths and image size are the commands' defaults
# (lens-trace(1) --sensor and --lambda, lens-spot(1) --fields and --wavelengths), and a
# fitted system answers only inside the domain it was fitted over (--compare).
# References: the paraxial image height efl tan(angle) with efl from lens-info, the real
# chief-ray height from lens-distort, and the file's own lists.
source "$(dirname "$0")/lib.sh"

Z=lenses/cooke-triplet.zmx # YFLN 0 14 20, WAVM F d C (PWAV 2), no sensor
# the same lens with one paraxial image-height field of 10 mm and one wavelength
sed -e 's/^FTYP .*/FTYP 2 0 2 1 0 0 0/' -e 's/^XFLN .*/XFLN 0 0/' -e 's/^YFLN .*/YFLN 0 10/' \
    -e '/^WAVM [23]/d' -e 's/^WAVM 1 .*/WAVM 1 0.55 1/' -e 's/^PWAV .*/PWAV 1/' $Z >$T/ih.zmx

# the sensor: 3:2, its corner 3 % past the real chief ray of the largest field (20 deg)
run $BIN/lens-info $Z >$T/info.txt 2>/dev/null
run $BIN/lens-distort $Z --fields 20 --illum-rays 0 >$T/d20.txt 2>/dev/null
s=$(value sensor <$T/info.txt) h=$(awk '$1 == "lens" && $2 == 20 { print $3 }' $T/d20.txt)
if [ -n "$s" ] && [ -n "$h" ] &&
   awk -v s="$s" -v h="$h" 'BEGIN { split(s, p, "x"); r = sqrt(p[1]^2 + p[2]^2) / 2
     exit !((p[1] / p[2] - 1.5)^2 < 1e-8 && (r / (1.03 * h) - 1)^2 < 1e-8) }'
then ok file_sensor_from_largest_field; else fail file_sensor_from_largest_field "sensor '$s' chief height '$h'"; fi

# no flag: lens-trace takes that sensor, lens-fit the samples
if run $BIN/lens-trace $Z -n 3000 --seed 2 2>/dev/null >$T/s.txt &&
   grep -q "^# lens-trace .*lambda 0.4:0.7 um, sensor $s mm" $T/s.txt &&
   run $BIN/lens-fit -q --terms 30 -o $T/c.poly $T/s.txt 2>/dev/null
then ok file_trace_fit_no_flag; else fail file_trace_fit_no_flag "$(head -1 $T/s.txt)"; fi

# the analyses' defaults: the file's fields and wavelengths, its primary the primary
run $BIN/lens-spot $Z --rays 20 >$T/sp.txt 2>/dev/null
got=$(awk '!/^#/ && $1 == "lens" { f[$2] = 1; l[$3] = 1 } END { n = 0; for (k in f) n++; m = 0; for (k in l) m++
          print n, m, (0 in f) && (14 in f) && (20 in f), ("0.4861327" in l) && ("0.5875618" in l) && ("0.6562725" in l) && ("all" in l) }' $T/sp.txt)
if [ "$got" = "3 4 1 1" ]; then ok file_fields_and_wavelengths_default
else fail file_fields_and_wavelengths_default "$got: $(grep -v '^#' $T/sp.txt | cut -c1-40)"; fi

# a paraxial image height becomes the angle that images there: atan(h / efl) at the
# file's one wavelength, which is the default wavelength of lens-spot and lens-distort
run $BIN/lens-info $T/ih.zmx --wavelength 0.55 >$T/ih-info.txt 2>/dev/null
efl=$(value efl <$T/ih-info.txt)
run $BIN/lens-spot $T/ih.zmx --rays 20 >$T/ih.txt 2>/dev/null
run $BIN/lens-distort $T/ih.zmx --illum-rays 0 >$T/ihd.txt 2>/dev/null
top=$(awk '!/^#/ && $1 == "lens" { f = $2 } END { print f }' $T/ih.txt)
if [ -n "$efl" ] && near "$top" "$(awk -v f="$efl" 'BEGIN { printf "%.9f", atan2(10, f) * 45 / atan2(1, 1) }')" 1e-6 &&
   [ "$(awk '!/^#/ && $1 == "lens" { print $3 }' $T/ih.txt | sort -u | tr "\n" " ")" = "0.55 " ] &&
   near "$(awk '!/^#/ && $1 == "lens" { f = $2 } END { print f }' $T/ihd.txt)" "$top" 1e-6
then ok file_image_height_field; else fail file_image_height_field "efl $efl top $top $(cat $T/ih.txt)"; fi

# The wavelength band widens to hold the file's (0.8 um, inside N-SK16's and SF4's data).
sed -e 's/^WAVM 1 .*/WAVM 1 0.8 1/' $T/ih.zmx >$T/ir.zmx
if run $BIN/lens-trace $T/ir.zmx -n 200 2>/dev/null | grep -q "lambda 0.4:0.8 um"
then ok file_band_holds_file_wavelength; else fail file_band_holds_file_wavelength "$(run $BIN/lens-trace $T/ir.zmx -n 1 2>&1 | head -2)"; fi

# The domain: a field past the sensor the system was fitted over is nan with a warning
# naming the domain and exit 2; the file's top field is inside it and a number.
run $BIN/lens-distort $Z --compare $T/c.poly --fields 0,20,25 --illum-rays 0 >$T/dc.txt 2>$T/err.txt; rc=$?
if [ $rc -eq 2 ] && [ "$(awk '$1 == "poly" && $2 == 25 { print $3 }' $T/dc.txt)" = nan ] &&
   awk '$1 == "poly" && $2 == 20 && $3 > 18 && $3 < 18.5 { ok = 1 } END { exit !ok }' $T/dc.txt &&
   awk '$1 == "lens" && $2 == 25 && $3 > 23 { ok = 1 } END { exit !ok }' $T/dc.txt &&
   grep -q "warning: poly: field 25 deg .*outside the system's training domain (sensor radius up to" $T/err.txt
then ok compare_outside_domain_is_nan; else fail compare_outside_domain_is_nan "rc=$rc $(cat $T/err.txt)"; fi
run $BIN/lens-spot $Z --compare $T/c.poly --fields 25 --wavelengths d --rays 20 >$T/sc.txt 2>$T/err.txt; rc=$?
if [ $rc -eq 2 ] && awk '$1 == "poly" && $2 == 25 && $3 == "0.5875618" { ok = ($11 == "nan") } END { exit !ok }' $T/sc.txt &&
   grep -q "training domain" $T/err.txt
then ok spot_outside_domain_is_nan; else fail spot_outside_domain_is_nan "rc=$rc $(cat $T/err.txt $T/sc.txt)"; fi
# and a wavelength outside the band it was fitted over (0.4..0.7 um)
run $BIN/lens-spot $Z --compare $T/c.poly --fields 0 --wavelengths 0.75 --rays 20 >$T/sw.txt 2>$T/err.txt; rc=$?
if [ $rc -eq 2 ] && grep -q "0.75 um lies outside the system's training wavelengths" $T/err.txt
then ok spot_outside_band_is_nan; else fail spot_outside_band_is_nan "rc=$rc $(cat $T/err.txt)"; fi

# A file that states the axis alone gets the sensor of a 1 degree half field (its corner
# 3 % past the 1 degree chief ray), and its one field is the analyses' default.
sed -e 's/^FTYP .*/FTYP 0 0 1 3 0 0 0/' -e 's/^XFLN .*/XFLN 0/' -e 's/^YFLN .*/YFLN 0/' $Z >$T/axis.zmx
run $BIN/lens-distort $Z --fields 1 --illum-rays 0 >$T/d1.txt 2>/dev/null
s=$(run $BIN/lens-info $T/axis.zmx 2>/dev/null | value sensor) h=$(awk '$1 == "lens" && $2 == 1 { print $3 }' $T/d1.txt)
if [ -n "$s" ] && [ -n "$h" ] &&
   awk -v s="$s" -v h="$h" 'BEGIN { split(s, p, "x"); r = sqrt(p[1]^2 + p[2]^2) / 2; exit !((r / (1.03 * h) - 1)^2 < 1e-8) }' &&
   [ "$(run $BIN/lens-spot $T/axis.zmx --rays 20 2>/dev/null | awk '!/^#/ { print $2 }' | sort -u)" = 0 ]
then ok file_axis_only_sensor; else fail file_axis_only_sensor "sensor '$s' chief height at 1 deg '$h'"; fi
