#!/usr/bin/env bash
# lens-fan, lens-field, lens-mtf (and lens-layout): tables, closed forms through a
# perfect system, pictures, errors, no partial files.
source "$(dirname "$0")/lib.sh"
DG=lenses/dgauss.50mm.lens
W=tests/data/window.lens P=tests/data/perfect-50mm.poly

for c in fan field mtf layout; do
  if run $BIN/lens-$c --help | grep -q "^usage: lens-$c"; then ok designer_help_$c; else fail designer_help_$c; fi
done

# fans: header, a row per fan point; on the axis tangential and sagittal fans agree
run $BIN/lens-fan $DG --fields 0,10 --wavelengths d --points 9 >$T/f.txt 2>$T/err.txt
if head -1 $T/f.txt | grep -q '^# columns: model field_deg lambda_um fan pupil ex_um ey_um' &&
   [ "$(grep -vc '^#' $T/f.txt)" = 36 ] &&
   awk '$2 == 0 && $4 == "tan" { t[$5] = $7 } $2 == 0 && $4 == "sag" { s[$5] = $6 }
        END { for (k in t) if (t[k] != "nan" && (t[k] - s[k])^2 > 1e-12) exit 1 }' $T/f.txt
then ok designer_fan_table; else fail designer_fan_table "$(cat $T/err.txt; head -3 $T/f.txt)"; fi

# a perfect system: no ray error, chief ray at 50 sin(theta), foci on the sensor
run $BIN/lens-fan $W --compare $P --fields 5 --wavelengths d --points 5 >$T/p.txt 2>$T/err.txt
if awk '$1 == "poly" { n++; if ($6^2 + $7^2 > 1e-12) bad = 1 } END { exit bad || n != 10 }' $T/p.txt &&
   grep -q '^# time imaging the fans: lens .* s, poly .* s' $T/p.txt
then ok designer_fan_perfect_system; else fail designer_fan_perfect_system "$(cat $T/err.txt $T/p.txt)"; fi
run $BIN/lens-field $W --compare $P --fields 0,5,10 --wavelengths d >$T/c.txt 2>$T/err.txt
if awk '$1 == "poly" { n++; if ($5^2 + $6^2 > 1e-12) bad = 1
                       if (($4 - 50 * sin($2 * 3.14159265358979 / 180))^2 > 1e-14) bad = 1 }
        END { exit bad || n != 3 }' $T/c.txt
then ok designer_field_perfect_system; else fail designer_field_perfect_system "$(cat $T/err.txt $T/c.txt)"; fi

# the perfect system's diffraction MTF is the closed form of a circular pupil, with the
# numerical aperture the command reports
run $BIN/lens-mtf $W --compare $P --fields 0 --wavelengths d --pixel 1 --steps 5 >$T/m.txt 2>$T/err.txt
na=$(awk '$1 == "#" && $2 == "wavefront:" && $3 == "poly" { print ($9 < 0 ? -$9 : $9) }' $T/m.txt)
if [ -n "$na" ] && awk -v na="$na" '$1 == "poly" { v = $4 * 0.5875618e-3 / (2 * na); m = 0
        if (v < 1) m = 2 / 3.14159265358979 * (atan2(sqrt(1 - v * v), v) - v * sqrt(1 - v * v))
        if (($5 - m)^2 > 4e-6 || ($6 - m)^2 > 4e-6 || $7 != 1) bad = 1; n++ }
        END { exit bad || n != 6 }' $T/m.txt
then ok designer_mtf_closed_form; else fail designer_mtf_closed_form "$(cat $T/err.txt $T/m.txt)"; fi
# through focus: the perfect system is sharpest on its plane
run $BIN/lens-mtf $P --fields 0 --wavelengths d --through-focus 100 --focus-range 0.02 --focus-steps 5 \
    --grid 32 >$T/t.txt 2>$T/err.txt
if awk '!/^#/ { v[$4] = $5 } END { exit !(v[0] > v[0.01] && v[0.01] > v[0.02] && v[0] > v[-0.01]) }' $T/t.txt
then ok designer_mtf_through_focus; else fail designer_mtf_through_focus "$(cat $T/err.txt $T/t.txt)"; fi

# A plano-hyperbolic singlet (rear face k = -n^2) is perfect on its axis: the ray through
# stop height h = 5 p crosses the axis 100 - sag(h) behind the rear face, and its sensor
# lies 0.05 mm beyond that focus, so the fans are exactly -h 0.05 / (100 - sag(h)), and
# through focus the sharp plane is at -0.05 mm: the geometric MTF 1 there and the
# diffraction MTF the circular pupil's closed form (the MTFs fall on both sides)
H=tests/data/hyperbolic.lens
run $BIN/lens-fan $H --fields 0 --wavelengths d --points 9 >$T/hf.txt 2>$T/err.txt
if awk 'function ey(p,   h, c) { h = 5 * p; c = -0.02
          return -1000 * h * 0.05 / (100 - c * h * h / (1 + sqrt(1 + 1.25 * c * c * h * h))) }
        !/^#/ { n++; e = $4 == "tan" ? $7 : $6; o = $4 == "tan" ? $6 : $7
                if ((e - ey($5))^2 > 1e-10 || o != 0) bad = 1 }
        END { exit bad || n != 18 }' $T/hf.txt
then ok designer_fan_defocus_closed_form; else fail designer_fan_defocus_closed_form "$(cat $T/err.txt $T/hf.txt)"; fi
run $BIN/lens-mtf $H --fields 0 --wavelengths d --through-focus 100 --focus-range 0.1 --focus-steps 5 >$T/hm.txt 2>$T/err.txt
na=$(awk '$2 == "wavefront:" && $3 == "lens" { print $9 }' $T/hm.txt)
if [ -n "$na" ] && awk -v na="$na" '!/^#/ { d[$4] = $5; g[$4] = $7; s[$4] = $6 - $5 }
        END { v = 100 * 0.5875618e-3 / (2 * na); m = 2 / 3.14159265358979 * (atan2(sqrt(1 - v * v), v) - v * sqrt(1 - v * v))
              if ((d[-0.05] - m)^2 > 1e-5 || g[-0.05] < 0.99999 || s[-0.05] != 0) exit 1
              exit !(d[-0.05] > d[0] && d[-0.05] > d[-0.1] && d[0] > d[0.05] && g[0] < 0.9 && g[-0.1] < 0.9 && g[0.05] < g[0]) }' $T/hm.txt
then ok designer_mtf_through_focus_sign; else fail designer_mtf_through_focus_sign "$(cat $T/err.txt $T/hm.txt)"; fi

# A thin singlet (n 1.5, f 100) with its stop at the lens against third-order theory at
# image height h = f tan(theta): astigmatism T - S = -h^2 / f, Petzval -h^2 / (2 n f);
# its chief ray passes the centre undeviated, so no distortion (f tan against f sin
# would be 1.5 % at 10 degrees)
run $BIN/lens-info tests/data/thin-singlet.lens >$T/ti.txt 2>/dev/null
efl=$(awk '$1 == "efl" { print $2 }' $T/ti.txt)
# on the axis the tangential and sagittal foci are one: astigmatism 0, not round-off
if [ "$(run $BIN/lens-field lenses/sasian-triplet.zmx --fields 0 2>/dev/null | awk '!/^#/ && $1 == "lens" { print $7 }' | sort -u)" = 0 ]
then ok field_axis_astigmatism_zero; else fail field_axis_astigmatism_zero; fi
run $BIN/lens-field tests/data/thin-singlet.lens --fields 1,1.5,10 --wavelengths d --focus paraxial >$T/ts.txt 2>$T/err.txt
if [ -n "$efl" ] && awk -v f="$efl" '!/^#/ { n++; h = f * sin($2 * 3.14159265358979 / 180) / cos($2 * 3.14159265358979 / 180)
          if ($2 < 5 && (($7 / (-h * h / f) - 1)^2 > 1e-4 || ($8 / (-h * h / (3 * f)) - 1)^2 > 1e-4)) bad = 1
          if ($2 == 10 && $9^2 > 0.01^2) bad = 1 }
        END { exit bad || n != 3 }' $T/ts.txt
then ok designer_field_seidel_columns; else fail designer_field_seidel_columns "$(cat $T/err.txt $T/ts.txt)"; fi

# Lateral colour of a thin singlet with its stop d = 20 mm in front: the chief ray meets
# the lens at d tan(theta), so the F image lies below the C image by (d / f) h / V_d
# (h = f tan(theta)); the primary wavelength is the reference (0). Distortion is the
# chief-ray height against efl tan(theta) (efl from lens-info).
run $BIN/lens-info tests/data/thin-singlet-front-stop.lens >$T/fi.txt 2>/dev/null
efl=$(awk '$1 == "efl" { print $2 }' $T/fi.txt)
run $BIN/lens-field tests/data/thin-singlet-front-stop.lens --fields 1,2 --focus paraxial >$T/fs.txt 2>$T/err.txt
if [ -n "$efl" ] && awk -v f="$efl" '!/^#/ { n++; h = f * sin($2 * 3.14159265358979 / 180) / cos($2 * 3.14159265358979 / 180)
          lc[$2, $3] = $10; if ((100 * ($4 - h) / h - $9)^2 > 1e-8 + ($9 * 1e-5)^2) bad = 1
          if ($3 == 0.5875618 && $10 != 0) bad = 1 }
        END { for (t = 1; t <= 2; t++) { h = f * sin(t * 3.14159265358979 / 180) / cos(t * 3.14159265358979 / 180)
                e = -1000 * 20 / f * h / 64.17; if (((lc[t, "0.4861327"] - lc[t, "0.6562725"]) / e - 1)^2 > 0.005^2) bad = 1 }
              exit bad || n != 6 }' $T/fs.txt
then ok designer_lateral_colour_closed_form; else fail designer_lateral_colour_closed_form "$(cat $T/err.txt $T/fs.txt)"; fi

# Through a fitted (meridional) system every ray of the axial wavefront that the lens
# passes is imaged, at every wavelength: Newton seeded from a chief ray a hair on the
# wrong side of the axis stalled for most of the C-line pupil (236 of 856 cells), the
# rest seeded from solved neighbours; and on the axis tangential equals sagittal
run $BIN/lens-trace lenses/sasian-triplet.zmx --sensor 29x22 -n 5000 --seed 1 -o $T/st.txt >/dev/null 2>&1
run $BIN/lens-fit -q -o $T/st.poly $T/st.txt >/dev/null 2>&1
run $BIN/lens-mtf lenses/sasian-triplet.zmx --compare $T/st.poly --fields 0 --focus paraxial --grid 32 >$T/sm.txt 2>$T/err.txt
if awk '$2 == "wavefront:" && $3 != "model" { n++; c[$3, $5] = $6 }
        $1 == "poly" && ($5 - $6)^2 > 1e-4 { bad = 1 }
        END { for (k in c) { split(k, p, SUBSEP); if (p[1] == "poly" && c[k] != c["lens", p[2]]) bad = 1 }
              exit bad || n != 6 }' $T/sm.txt
then ok designer_system_images_every_ray; else fail designer_system_images_every_ray "$(cat $T/err.txt; grep '^#' $T/sm.txt)"; fi

# the focal shift through the system too: its time and its largest difference from the lens
run $BIN/lens-field lenses/sasian-triplet.zmx --compare $T/st.poly --focal-shift 5 >$T/sf.txt 2>$T/err.txt
if grep -q '^# time imaging the close rays: lens .* s, poly .* s' $T/sf.txt &&
   awk '$1 == "lens" { l[$2] = $3 } $1 == "poly" { p[$2] = $3 }
        /^# poly - lens: focal shifts differ by at most / { said = $(NF - 1) }
        END { for (k in l) { d = p[k] - l[k]; if (d < 0) d = -d; if (d > m) m = d }
              exit !(length(l) == 5 && m > 0 && (said / m - 1)^2 < 1e-6) }' $T/sf.txt
then ok designer_focal_shift_system; else fail designer_focal_shift_system "$(cat $T/err.txt $T/sf.txt)"; fi

# focal shift: the close-ray focus agrees with the paraxial one
run $BIN/lens-field lenses/cooke-triplet.zmx --focal-shift 5 >$T/s.txt 2>$T/err.txt
if awk '!/^#/ { n++; if (($3 - $4)^2 > 1e-4) bad = 1 } END { exit bad || n != 5 }' $T/s.txt
then ok designer_focal_shift; else fail designer_focal_shift "$(cat $T/err.txt $T/s.txt)"; fi

# pictures
for c in fan field mtf; do
  run $BIN/lens-$c $DG --fields 0,10 --png $T/$c.png >/dev/null 2>$T/err.txt
  if [ "$(head -c 4 $T/$c.png 2>/dev/null | od -An -tx1 | tr -d ' ')" = 89504e47 ]
  then ok designer_png_$c; else fail designer_png_$c "$(cat $T/err.txt)"; fi
done

# errors: one line naming the problem; a picture that cannot be written leaves nothing
expect_error designer_bad_wavefront "--wavefront" run $BIN/lens-mtf $DG --wavefront exact
expect_error designer_bad_pixel "--pixel" run $BIN/lens-mtf $DG --pixel 0
expect_error designer_bad_points "--points" run $BIN/lens-fan $DG --points 1
expect_error designer_no_lens "no lens given" run $BIN/lens-field
run $BIN/lens-mtf $DG --fields 0 --png $T/no/such/dir/x.png >/dev/null 2>&1
if [ $? -ne 0 ] && [ -z "$(ls $T/no 2>/dev/null)" ]; then ok designer_png_error; else fail designer_png_error; fi

# layout: the surface table, every ray of a plain lens reaches the sensor, PNG and SVG
run $BIN/lens-layout lenses/cooke-triplet.zmx --fields 0,20 --rays 5 --png $T/l.png --svg $T/l.svg >$T/l.txt 2>$T/err.txt
if head -1 $T/l.txt | grep -q '^# columns: surface z_mm radius_mm conic semi_diameter_mm sag_rim_mm material stop' &&
   [ "$(grep -vc '^#' $T/l.txt)" = 7 ] && grep -q '^# rays at 0.5875618 um: 10 of 10 reach the sensor' $T/l.txt &&
   [ "$(head -c 4 $T/l.png | od -An -tx1 | tr -d ' ')" = 89504e47 ] &&
   [ "$(grep -c '<polygon' $T/l.svg)" = 3 ] && [ "$(grep -c '<polyline' $T/l.svg)" -ge 14 ] && tail -1 $T/l.svg | grep -q '</svg>'
then ok designer_layout; else fail designer_layout "$(cat $T/err.txt $T/l.txt)"; fi
# through a system: its rays beside the lens's, and their difference
run $BIN/lens-layout $W --compare $P --fields 0,5 --rays 3 --svg $T/w.svg >$T/w.txt 2>$T/err.txt
if grep -q '^# poly - lens: sensor points differ by at most' $T/w.txt && grep -q 'stroke-dasharray="1 1"' $T/w.svg
then ok designer_layout_system; else fail designer_layout_system "$(cat $T/err.txt $T/w.txt)"; fi
run $BIN/lens-layout $DG --svg $T/no/such/dir/x.svg >/dev/null 2>&1
if [ $? -ne 0 ] && [ -z "$(ls $T/no 2>/dev/null)" ]; then ok designer_svg_error; else fail designer_svg_error; fi

# --json: one valid object with the tables by name
for c in fan field mtf layout; do
  run $BIN/lens-$c $DG --fields 0,10 --wavelengths d --json >$T/$c.json 2>$T/err.txt
  if python3 -c "import json, sys; d = json.load(open(sys.argv[1])); assert 'setup' in d and len(d) >= 3" $T/$c.json
  then ok designer_json_$c; else fail designer_json_$c "$(cat $T/err.txt; head -c 300 $T/$c.json)"; fi
done

# every lens's report opens with its layout: the first picture of reports/<lens>.md is
# lenses/<lens>-layout.png, and that picture is there
missing=
for l in lenses/*.lens; do
  n=$(basename "$l" .lens) r=reports/$(basename "$l" .lens).md
  first=$(grep -m1 -o '!\[[^]]*\]([^)]*)' "$r" 2>/dev/null | sed 's/.*(\(.*\))/\1/')
  [ "$first" = "lenses/$n-layout.png" ] && [ -s "reports/lenses/$n-layout.png" ] || missing="$missing $n"
done
if [ -z "$missing" ]; then ok designer_layout_first_in_reports; else fail designer_layout_first_in_reports "not first or missing:$missing"; fi
