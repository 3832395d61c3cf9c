#!/usr/bin/env bash
# lens-spot: the table, pictures read back, focus, errors, no partial files.
source "$(dirname "$0")/lib.sh"
S=$BIN/lens-spot
DG=lenses/dgauss.50mm.lens
rays=200; [ -n "${SANITIZE:-}" ] && rays=40

if run $S --help | grep -q '^usage: lens-spot'; then ok spot_help; else fail spot_help; fi

# the table: a header naming the columns, a row per field and wavelength, "all" per field
run $S $DG --fields 0,10,14 --rays $rays >$T/s.txt 2>$T/err.txt
if head -1 $T/s.txt | grep -q '^# columns: model field_deg lambda_um rays passed vignetted .* rms_centroid_um' &&
   [ "$(grep -vc '^#' $T/s.txt)" = 12 ] && [ "$(awk '$3 == "all"' $T/s.txt | wc -l)" = 3 ]
then ok spot_table; else fail spot_table "$(cat $T/err.txt; head -3 $T/s.txt)"; fi
# the chief ray of a field lies where lens-distort puts it (two paths to the same ray)
y1=$(awk '$2 == 10 && $3 == 0.5875618 { print $8 }' $T/s.txt)
y2=$(run $BIN/lens-distort $DG --fields 0,10 --illum-rays 0 | awk '!/^#/ && $2 == 10 { print $3 }')
if near "$y1" "$y2" 1e-9; then ok spot_chief_matches_distort; else fail spot_chief_matches_distort "$y1 vs $y2"; fi

# best focus is never worse than the file's plane (summed over fields and wavelengths)
run $S $DG --fields 0,10 --rays $rays --focus best >$T/b.txt
b=$(awk '!/^#/ && $3 != "all" && ($2 == 0 || $2 == 10) { s += $13 * $13 } END { print s }' $T/b.txt)
a=$(awk '!/^#/ && $3 != "all" && ($2 == 0 || $2 == 10) { s += $13 * $13 } END { print s }' $T/s.txt)
if awk -v a="$a" -v b="$b" 'BEGIN { exit !(b <= a + 1e-9) }' && grep -q '^# sensor plane moved' $T/b.txt
then ok spot_best_focus; else fail spot_best_focus "best $b file $a"; fi

# pictures: a PNG of the expected size, an EXR with its magic number
run $S $DG --fields 0,14 --rays $rays --png $T/s.png --exr $T/s.exr >$T/p.txt 2>$T/err.txt
size=$(od -An -tu1 -j16 -N8 $T/s.png 2>/dev/null | awk '{ print $3 * 256 + $4, $7 * 256 + $8 }')
w=${size% *}
if [ "$(head -c 4 $T/s.png | od -An -tx1 | tr -d ' ')" = 89504e47 ] && [ "${w:-0}" -ge 600 ]
then ok spot_png; else fail spot_png "size '$size' $(cat $T/err.txt)"; fi
if [ "$(head -c 4 $T/s.exr | od -An -tx1 | tr -d ' ')" = 762f3101 ] && grep -q '^# exr .*um per pixel' $T/p.txt
then ok spot_exr; else fail spot_exr "$(cat $T/err.txt)"; fi

# errors: one line naming the problem
expect_error spot_unknown_wavelength "unknown wavelength 'X'" run $S $DG --wavelengths d,X
expect_error spot_field_too_far "field 80 deg: no chief ray" run $S $DG --fields 0,80 --rays 10
expect_error spot_empty_fields "empty field list" run $S $DG --fields ''
expect_error spot_bad_field "bad field 'ten'" run $S $DG --fields 0,ten
expect_error spot_no_file "nonexistent.lens" run $S $T/nonexistent.lens
expect_error spot_bad_focus "--focus" run $S $DG --focus sharp
# a picture that cannot be written leaves nothing behind
run $S $DG --fields 0 --rays 10 --png $T/no/such/dir/x.png >/dev/null 2>&1
if [ $? -ne 0 ] && [ -z "$(ls $T/no 2>/dev/null)" ]; then ok spot_png_error; else fail spot_png_error; fi

# --compare: a window does not focus (its spot is the 10 mm stop: radius 5000 um about the
# centroid), the perfect system beside it does (RMS 0), at 50 sin(theta)
run $S tests/data/window.lens --compare tests/data/perfect-50mm.poly --fields 0,5 --wavelengths d \
    --rays 61 --png $T/c.png >$T/c.txt 2>$T/err.txt
if awk '$1 == "lens" { if (($14 - 5000)^2 > 1e-6) bad = 1; n++ }
        $1 == "poly" { if ($13 > 1e-6) bad = 1; if (($10 - 50 * sin($2 * 3.14159265358979 / 180))^2 > 1e-14) bad = 1; m++ }
        END { exit bad || n != 2 || m != 2 }' $T/c.txt && [ -s $T/c.png ]
then ok spot_compare; else fail spot_compare "$(cat $T/err.txt $T/c.txt)"; fi
# a system on its own finds its lens through the path it records
if [ "$(run $S tests/data/perfect-50mm.poly --fields 10 --wavelengths d --rays 7 | awk '$1 == "poly" { print $8 }')" = 8.68240888 ]
then ok spot_system_alone; else fail spot_system_alone; fi
# a system fitted to another lens: said on stderr (and in the JSON); its own lens: not
if ! grep -q "fitted to" $T/err.txt &&
   run $S $DG --compare tests/data/perfect-50mm.poly --fields 0 --wavelengths d --rays 7 --json 2>$T/err2.txt >$T/c2.json &&
   grep -q "^lens-spot: warning: the system was fitted to 'perfect' (tests/data/window.lens), not to this lens" $T/err2.txt &&
   python3 -c 'import json,sys; w=json.load(open(sys.argv[1]))["warnings"]; sys.exit(not any("fitted to" in x for x in w))' $T/c2.json
then ok spot_compare_other_lens; else fail spot_compare_other_lens "$(cat $T/err.txt $T/err2.txt)"; fi
# a system of samples traced to the stop cannot be shown
sed '/^pass /a meta trace_frame stop' tests/data/perfect-50mm.poly >$T/stop.poly
expect_error spot_system_to_stop "fitted to samples traced to the stop" $S lenses/dgauss.50mm.lens --compare $T/stop.poly --fields 0
expect_error spot_compare_not_a_system "lens-poly|poly" run $S $DG --compare $DG

# The README's comparison through the default pipeline (lens-trace | lens-fit): the
# system's spot RMS is the lens's within 1% at 0, 10 and 14 degrees, with the same
# vignetted fractions. The outer pupil's directions once sat in a frame that does not
# turn with the ray and were fitted outside the meridional frame: 25 times the direction
# error, -0.5% and -1% at 10 and 14 degrees; the axis took +2.6% to +7.8% (over training
# seeds) until a sixteenth of lens-trace's pupil-sampled rays went near the axis, the
# edge of a meridional fit's data (-0.6% here; seeds 2-4: -0.5%, +0.9%, -0.4%).
if [ -z "${SANITIZE:-}" ]; then
  run $BIN/lens-trace $DG -n 20000 -o $T/readme-train.txt 2>/dev/null
  run $BIN/lens-fit -q -o $T/readme.poly $T/readme-train.txt
  run $S $DG --compare $T/readme.poly --fields 0,10,14 --wavelengths d >$T/rc.txt 2>&1
  if awk '$1 == "lens" { l[$2] = $11; v[$2] = $6 } $1 == "poly" { p[$2] = $11; w[$2] = $6 }
          END { for (f in l) { d = p[f] / l[f] - 1; lim = 0.01
                  printf "# spot_readme_compare: field %s rms %+.2f%% vignetted %+.4f\n", f, 100 * d, w[f] - v[f]
                  if (!(d * d < lim * lim) || (w[f] - v[f]) ^ 2 > 1e-4) bad = 1 }
                exit bad || length(l) != 3 }' $T/rc.txt
  then ok spot_readme_compare; else fail spot_readme_compare "$(cat $T/rc.txt)"; fi
  # lens-mtf seeds an on-axis bundle's Newton solves with the chief ray, (0, 0, 0, 0):
  # there a meridional system's Jacobian has no y column, and with every outer output
  # in the frame no pupil cell solved (poly_solve.c starts a nanometre off the axis)
  run $BIN/lens-mtf $DG --compare $T/readme.poly --fields 0 --wavelengths d --steps 4 >$T/rm.txt 2>&1
  if awk '$1 == "poly" && $4 == 50 { n++ } END { exit n != 1 }' $T/rm.txt
  then ok mtf_readme_compare_axis; else fail mtf_readme_compare_axis "$(tail -2 $T/rm.txt)"; fi
  # each model's wavefront method is named (a system alone had been said to have the
  # lens's "by path lengths")
  if grep -q '^# pixel .*; lens wavefront by path lengths; system wavefront by ray errors$' $T/rm.txt &&
     run $BIN/lens-mtf $T/readme.poly --fields 0 --wavelengths d --steps 4 2>/dev/null |
       grep -q '^# pixel .*64; system wavefront by ray errors$'
  then ok mtf_wavefront_methods; else fail mtf_wavefront_methods "$(grep '^# pixel' $T/rm.txt)"; fi
fi
