#!/usr/bin/env bash
# What an adversarial review tried, each answered by a clear one-line error (or a
# warning where a result is still whole), a non-zero exit and no partial output file;
# names from input files never forge a line of a text table.
source "$(dirname "$0")/lib.sh"
LENS=lenses/dgauss.50mm.lens
# no_ctl NAME FILE: the file holds no control byte but tab and newline.
no_ctl() {
  if LC_ALL=C grep -q $'[\x01-\x08\x0b-\x1f\x7f]' "$2"; then
    fail "$1" "$(LC_ALL=C grep -m1 $'[\x01-\x08\x0b-\x1f\x7f]' "$2" | cat -v)"
  else ok "$1"; fi
}

# ---- names from input files in text output: control bytes escaped as \xNN -----------
# (\r, \v and \f end a line for many readers; ESC drives a terminal)
{ printf '# name: evil\rname\x0bX\x1b[31mRED\n'; tail -n +2 lenses/simple.lens; } >"$T/evil.lens"
run $BIN/lens-info "$T/evil.lens" >"$T/info.txt" 2>/dev/null
no_ctl info_name_escaped "$T/info.txt"
grep -qF 'name evil\x0dname\x0bX\x1b[31mRED' "$T/info.txt" && ok info_name_shown ||
  fail info_name_shown "$(grep '^name' "$T/info.txt" | cat -v)"
run $BIN/lens-spot "$T/evil.lens" --fields 0 >"$T/spot.txt" 2>/dev/null
no_ctl spot_name_escaped "$T/spot.txt"
grep -qF '# evil\x0dname\x0bX\x1b[31mRED: f/' "$T/spot.txt" && ok spot_name_shown ||
  fail spot_name_shown "$(grep evil "$T/spot.txt" | cat -v)"
run $BIN/lens-trace "$T/evil.lens" -n 2 >"$T/trace.txt" 2>/dev/null
no_ctl trace_name_escaped "$T/trace.txt"
[ "$(grep -c '^# lens: evil\\x0dname' "$T/trace.txt")" = 1 ] && ok trace_name_shown ||
  fail trace_name_shown "$(grep 'lens:' "$T/trace.txt" | cat -v)"
# a lens path with a control byte: escaped in comment lines, and not recorded as the
# samples' lens-path (escaped, it would name another file)
cp lenses/simple.lens "$T/e"$'\x1b'"x.lens"
run $BIN/lens-trace "$T/e"$'\x1b'"x.lens" -n 2 >"$T/tpath.txt" 2>/dev/null
no_ctl trace_path_escaped "$T/tpath.txt"
grep -q '^# lens-path' "$T/tpath.txt" && fail trace_path_not_recorded "$(grep lens-path "$T/tpath.txt")" ||
  ok trace_path_not_recorded
run $BIN/lens-distort "$T/e"$'\x1b'"x.lens" --map "$T/map.txt" >/dev/null 2>&1
no_ctl distort_map_path_escaped "$T/map.txt"

# ---- absurd numbers: refused with the accepted range, never nan with exit 0 ------------
err_one mtf_pixel_range '^lens-mtf: --pixel: must lie in \[0.01, 10000\], not 1e-320$' \
  $BIN/lens-mtf $LENS --pixel 1e-320
err_one mtf_through_focus_range '^lens-mtf: --through-focus: must lie in \[1e-06, 100000\], not 1e308$' \
  $BIN/lens-mtf $LENS --through-focus 1e308
err_one mtf_focus_range_range '^lens-mtf: --focus-range: must lie in \[1e-06, 1000\]' \
  $BIN/lens-mtf $LENS --through-focus 10 --focus-range 1e308
err_one spot_fnumber_range "^lens-spot: $LENS: f/1e\\+308 is outside the accepted range f/2.03 .* to f/10000$" \
  $BIN/lens-spot $LENS --fnumber 1e308
err_one trace_fnumber_range "^lens-trace: $LENS: f/1e\\+308 is outside the accepted range" \
  $BIN/lens-trace $LENS --fnumber 1e308 -n 3
# the slowest accepted stop still gives numbers: an Airy radius of 1.22 lambda N
# (awk takes "nan" for a number that is near everything: it is checked apart)
airy=$(run $BIN/lens-spot $LENS --fnumber 1e4 --fields 0 --wavelengths d 2>/dev/null | awk '$1 == "lens" { print $NF }')
[[ $airy =~ ^[0-9.]+$ ]] && near "$airy" "$(awk 'BEGIN { print 1.22 * 0.5875618 * 1e4 }')" 1 && ok spot_fnumber_slowest ||
  fail spot_fnumber_slowest "airy '$airy'"

# ---- nothing written before an error -----------------------------------------------
# lens-trace --passing-only through a stop that passes next to nothing: refused before
# the preamble and the header, on stdout as with -o
out=$(run $BIN/lens-trace $LENS --passing-only --fnumber 1e4 -n 100 2>"$T/err"); rc=$?
[ $rc -ne 0 ] && [ -z "$out" ] && grep -q 'only 0 of the first 65536 traced rays pass the lens' "$T/err" &&
  ok trace_refused_before_output || fail trace_refused_before_output "rc $rc, $(wc -c <<<"$out") bytes on stdout"
run $BIN/lens-trace $LENS --passing-only --fnumber 1e4 -n 100 -o "$T/few.txt" 2>/dev/null
[ ! -e "$T/few.txt" ] && ok trace_refused_no_file || fail trace_refused_no_file
# a stop that passes few rays but enough: the rows all pass
run $BIN/lens-trace $LENS --passing-only --fnumber 100 -n 50 >"$T/slow.txt" 2>/dev/null &&
  [ "$(awk '!/^#/ && $10 > 0' "$T/slow.txt" | wc -l)" = 50 ] && ok trace_slow_stop_passes ||
  fail trace_slow_stop_passes "$(grep -vc '^#' "$T/slow.txt") rows"
# pictures: every output path checked before drawing, and removed when the table on
# standard output is lost
err_one layout_svg_unwritable '^lens-layout: /nonexistent/dir/x.svg: cannot write: No such file or directory$' \
  $BIN/lens-layout $LENS --png "$T/lay.png" --svg /nonexistent/dir/x.svg
[ ! -e "$T/lay.png" ] && ok layout_svg_unwritable_no_png || fail layout_svg_unwritable_no_png "lay.png left"
err=$(run $BIN/lens-spot $LENS --png "$T/spot.png" 2>&1 >&-); rc=$?
[ $rc -eq 1 ] && [ "$err" = "lens-spot: <stdout>: cannot write: Bad file descriptor" ] && [ ! -e "$T/spot.png" ] &&
  ok spot_stdout_closed_no_png || fail spot_stdout_closed_no_png "rc $rc '$err' $(ls "$T"/spot.png 2>&1)"
if [ -w /dev/full ]; then
  # a later picture that fails takes the earlier one with it
  err_one layout_svg_full_no_png '^lens-layout: /dev/full: write error: No space left on device$' \
    $BIN/lens-layout $LENS --png "$T/lay.png" --svg /dev/full
  [ ! -e "$T/lay.png" ] && ok layout_svg_full_png_removed || fail layout_svg_full_png_removed
  err_one spot_exr_full_no_png '^lens-spot: /dev/full: cannot write: No space left on device$' \
    $BIN/lens-spot $LENS --png "$T/spot.png" --exr /dev/full
  [ ! -e "$T/spot.png" ] && ok spot_exr_full_png_removed || fail spot_exr_full_png_removed
  for c in "lens-spot --png $T/full.png --exr $T/full.exr" "lens-layout --png $T/full.png --svg $T/full.svg" \
           "lens-mtf --fields 0 --png $T/full.png" "lens-distort --png $T/full.png"; do
    set -- $c
    err=$(run $BIN/$1 $LENS "${@:2}" 2>&1 >/dev/full); rc=$?
    left=$(ls "$T"/full.* 2>/dev/null)
    [ $rc -eq 1 ] && grep -qx "$1: <stdout>: write error: No space left on device" <<<"$err" && [ -z "$left" ] &&
      ok "${1}_stdout_full_no_picture" || fail "${1}_stdout_full_no_picture" "rc $rc '$err' left '$left'"
    rm -f "$T"/full.*
  done
fi

# ---- systems: values the commands act on are checked where their line is known -------
P=tests/data/perfect-50mm.poly
awk '/^pass / {print; print "meta fnumber 0"; next} {print}' $P >"$T/f0.poly"
line=$(grep -n '^meta fnumber' "$T/f0.poly" | cut -d: -f1)
err_one poly_meta_fnumber_zero "^lens-spot: $T/f0.poly:$line: meta fnumber '0' is not an f-number > 0$" \
  $BIN/lens-spot "$T/f0.poly"
err_one poly_meta_fnumber_eval "^lens-eval: $T/f0.poly:$line: meta fnumber" $BIN/lens-eval "$T/f0.poly" </dev/null
# a recorded f-number the lens cannot take: the system named as the file to correct
awk '/^pass / {print; print "meta fnumber 1e308"; next} {print}' $P >"$T/fbig.poly"
err_one poly_meta_fnumber_lens "^lens-spot: $T/fbig.poly: meta fnumber: tests/data/window.lens: f/1e\\+308" \
  $BIN/lens-spot "$T/fbig.poly"
# "meta passage full" with no pass circle: a claim nothing backs, refused at its line;
# with the circle the same system is read and shown
awk '/^pass / {print "meta passage full"; next} {print}' $P >"$T/nopass.poly"
line=$(grep -n '^meta passage' "$T/nopass.poly" | cut -d: -f1)
err_one poly_passage_full_no_pass "^lens-spot: $T/nopass.poly:$line: 'meta passage full' but no pass circle" \
  $BIN/lens-spot "$T/nopass.poly"
awk '/^pass / {print; print "meta passage full"; next} {print}' $P >"$T/pass.poly"
run $BIN/lens-spot "$T/pass.poly" >/dev/null 2>&1 && ok poly_passage_full_with_pass || fail poly_passage_full_with_pass

# ---- scenes --------------------------------------------------------------------------
# focus (or fstop) on a fitted .poly camera: refused with the scene's file and line, or
# with the option that asked
sed "s|^lens-path tests/|lens-path $TOP/tests/|" $P >"$T/cam.poly"
printf 'camera cam.poly\nsensor 36 24\nresolution 8 6\nspp 1\nfocus 1000\nplane 0 0 1000 0 0 -1 emit 1\n' >"$T/pf.scene"
err_one scene_poly_focus_line "^lens-render: $T/pf.scene:5: focus cannot change a fitted .poly camera" \
  $BIN/lens-render "$T/pf.scene" -q -o "$T/pf.exr"
sed 's/^focus 1000$/fstop 8/' "$T/pf.scene" >"$T/ps.scene"
err_one scene_poly_fstop_line "^lens-render: $T/ps.scene:5: fstop cannot change a fitted .poly camera" \
  $BIN/lens-render "$T/ps.scene" -q -o "$T/pf.exr"
[ ! -e "$T/pf.exr" ] && ok scene_poly_focus_no_file || fail scene_poly_focus_no_file
# a coordinate past the documented bound (1e9 mm): refused with its line, no image
printf 'camera dgauss.50mm\nsensor 36 24\nresolution 8 6\nspp 1\nsphere 0 0 1e160 1 emit 1\n' >"$T/far.scene"
err_one scene_far_emitter "^lens-render: $T/far.scene:5: position 1e160 mm is outside -1e\\+09 to 1e\\+09 mm$" \
  $BIN/lens-render "$T/far.scene" -q --exact -o "$T/far.exr"
[ ! -e "$T/far.exr" ] && ok scene_far_no_file || fail scene_far_no_file
# --emit-camera onto a full device: the write error and its reason, not a name question
if [ -w /dev/full ]; then
  printf 'camera simple.lens\nsensor 36 24\nresolution 8 6\nspp 1\nplane 0 0 1000 0 0 -1 emit 1\n' >"$T/emit.scene"
  cp lenses/simple.lens "$T/"
  err=$(run $BIN/lens-render "$T/emit.scene" --emit-camera /dev/full --cache "$T/cache" -q 2>&1); rc=$?
  [ $rc -ne 0 ] && [ "$err" = "lens-render: /dev/full: write error: No space left on device" ] &&
    ok render_emit_camera_full || fail render_emit_camera_full "rc $rc '$err'"
  err=$(run $BIN/lens-render "$T/emit.scene" --emit-camera /nonexistent/dir/cam.c --cache "$T/cache" -q 2>&1); rc=$?
  [ $rc -ne 0 ] && grep -qx 'lens-render: /nonexistent/dir/cam\.[ch]: cannot write: No such file or directory' <<<"$err" &&
    ok render_emit_camera_no_dir || fail render_emit_camera_no_dir "rc $rc '$err'"
fi

# ---- a wavelength outside a glass's range: the lens (file and line) and the glass named
err_one trace_lambda_model_glass \
  '^lens-trace: .*lenses/simple.lens:8: surface 1: wavelength 0.2 um is outside the range 0.36..1 um of the model glass nd 1.5 vd 54$' \
  $BIN/lens-trace lenses/simple.lens --lambda 0.2 -n 3
err_one trace_lambda_catalog_glass \
  '^lens-trace: .*lenses/lensbaby.lens:9: surface 1: wavelength 0.2 um is outside the range 0.35..2.5 um of glass N-SSK8$' \
  $BIN/lens-trace lenses/lensbaby.lens --lambda 0.2 -n 3

# ---- what a filter writes, the sample reader reads back: at most 64 columns ----------
run $BIN/lens-trace lenses/simple.lens -n 300 --seed 2 --no-passage-columns 2>/dev/null |
  run $BIN/lens-fit -q --terms 6 --degree 3 -o "$T/s5.poly" 2>/dev/null
wide() { # wide N: a ray file of x y u v lambda and N more columns
  awk -v n="$1" 'BEGIN { h = "# columns: x y u v lambda"; for (i = 0; i < n; i++) h = h " c" i; print h
    for (r = 0; r < 3; r++) { l = "0.1 0.2 0.01 0.02 0.55"; for (i = 0; i < n; i++) l = l " " i; print l } }'
}
wide 59 >"$T/w64.txt"   # 64 columns in: read, but 69 out
out=$(run $BIN/lens-eval "$T/s5.poly" "$T/w64.txt" 2>"$T/err"); rc=$?
[ $rc -ne 0 ] && [ -z "$out" ] &&
  grep -qx "lens-eval: $T/w64.txt:1: the output would have 69 columns (10 written and 59 passed through), more than a sample file holds (64); drop some input columns" "$T/err" &&
  ok eval_columns_over_limit || fail eval_columns_over_limit "rc $rc $(wc -c <<<"$out") bytes: $(cat "$T/err")"
out=$(run $BIN/lens-trace lenses/simple.lens - <"$T/w64.txt" 2>"$T/err"); rc=$?
[ $rc -ne 0 ] && [ -z "$out" ] && grep -q '<stdin>:1: the output would have 71 columns' "$T/err" &&
  ok trace_columns_over_limit || fail trace_columns_over_limit "rc $rc $(wc -c <<<"$out") bytes: $(cat "$T/err")"
# 54 extra columns make 64 out: written, and read back (the values through)
wide 54 >"$T/w59.txt"
if run $BIN/lens-eval "$T/s5.poly" "$T/w59.txt" >"$T/o64.txt" 2>/dev/null &&
   [ "$(grep '^# columns:' "$T/o64.txt" | wc -w)" = 66 ] &&
   run $BIN/lens-eval "$T/s5.poly" "$T/o64.txt" >"$T/o64b.txt" 2>/dev/null &&
   [ "$(awk '!/^#/ { print $NF }' "$T/o64b.txt" | sort -u)" = 53 ]
then ok eval_columns_at_limit_read_back; else fail eval_columns_at_limit_read_back; fi
# every designer command checks its picture path before it writes its table
for c in spot distort fan field mtf layout; do
  out=$(run $BIN/lens-$c $LENS --png /nonexistent/dir/x.png 2>"$T/err"); rc=$?
  [ $rc -eq 1 ] && [ -z "$out" ] && grep -qx "lens-$c: /nonexistent/dir/x.png: cannot write: No such file or directory" "$T/err" &&
    ok "${c}_png_checked_first" || fail "${c}_png_checked_first" "rc $rc, $(wc -c <<<"$out") bytes: $(cat "$T/err")"
done
