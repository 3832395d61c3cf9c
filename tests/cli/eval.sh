#!/usr/bin/env bash
# lens-eval: predictions, bad rows, extrapolation, the report, --emit c against itself.
source "$(dirname "$0")/lib.sh"
E=$BIN/lens-eval
tiny=tests/data/eval_tiny.poly

if run $E --help | grep -q '^usage: lens-eval'; then ok eval_help; else fail eval_help; fi

# predictions: out_x = x for rays the system passes; blocked rays get nan and out_eta 0
run $E $tiny tests/data/eval_tiny.txt >$T/pred.txt 2>$T/err.txt
if [ "$(grep -vc '^#' $T/pred.txt)" = 6 ] && head -1 $T/pred.txt | grep -q '^# columns: x y out_x out_u out_eta$' &&
   awk '!/^#/ && $1 <= 10 && ($3 != $1 || $5 != 1) { bad = 1 } !/^#/ && $1 > 10 && ($3 != "nan" || $5 != 0) { bad = 1 } END { exit bad }' $T/pred.txt
then ok eval_predictions; else fail eval_predictions "$(head -3 $T/pred.txt)"; fi
# extrapolation is reported, not silent (x = 20 and 50 lie outside the domain [-10, 10])
if grep -q '^lens-eval: 2 of 6 rays outside the training domain (extrapolated): x 2$' $T/err.txt
then ok eval_extrapolation; else fail eval_extrapolation "$(cat $T/err.txt)"; fi

# a system fitted at one wavelength (meta lambda, lambda not an input) on rays at others:
# evaluated, and counted (a 0.55 um fisheye-ii system had given a 0.1 mm RMS on a mixed
# test set, 250 times its error at 0.55 um, without a word)
sed '/^pass /a meta lambda 0.55' $tiny >$T/mono.poly
printf '# columns: x y lambda\n1 0 0.55\n2 0 0.55\n3 0 0.45\n' >$T/mono.txt
run $E $T/mono.poly $T/mono.txt >$T/mono.out 2>$T/err.txt
if [ "$(grep -vc '^#' $T/mono.out)" = 3 ] &&
   grep -q "^lens-eval: 1 of 3 rays at another wavelength than the system's 0.55 um" $T/err.txt &&
   ! run $E $tiny $T/mono.txt 2>&1 >/dev/null | grep -q "another wavelength"
then ok eval_other_wavelength; else fail eval_other_wavelength "$(cat $T/err.txt)"; fi

# a bad row: a nan row in its place, FILE:LINE on stderr, the rest evaluated, exit 1
printf '# columns: y x\n0 1\nzz 2\n0 3\n' >$T/bad.txt
run $E $tiny $T/bad.txt >$T/out.txt 2>$T/err.txt; rc=$?
if [ $rc -ne 0 ] && grep -q "bad.txt:3:" $T/err.txt && [ "$(sed -n 3p $T/out.txt)" = "nan nan nan nan nan" ] &&
   [ "$(awk 'NR == 4 { print $3 }' $T/out.txt)" = 3 ]
then ok eval_bad_row; else fail eval_bad_row "rc=$rc $(cat $T/err.txt) $(cat $T/out.txt)"; fi

# the report, against the hand computation in tests/unit/analysis/test_eval_report.c
run $E $tiny tests/data/eval_tiny.txt --report --bins 2 >$T/rep.txt 2>/dev/null
rms=$(awk '$1 == "out_x_mm" && NF == 7 { print $3 }' $T/rep.txt)
if head -1 $T/rep.txt | grep -q '^# columns: key rays rms mean p99 max unit' && near "$rms" 0.661438 1e-6 &&
   [ "$(awk '$1 == "false_pass" { print $2 }' $T/rep.txt)" = 1 ] && [ "$(awk '$1 == "false_block" { print $2 }' $T/rep.txt)" = 1 ]
then ok eval_report; else fail eval_report "$(head -3 $T/rep.txt)"; fi
# with the report the lens's reference is known: of the two rays outside, it passes x = 20
run $E $tiny tests/data/eval_tiny.txt --report >/dev/null 2>$T/err.txt
if grep -q '^lens-eval: 2 of 6 rays outside the training domain (extrapolated): x 2; the lens passes 1 of them: x 1$' $T/err.txt
then ok eval_extrapolation_lens_passes; else fail eval_extrapolation_lens_passes "$(cat $T/err.txt)"; fi
# a malformed row in a report: left out (rays 5 of 6 rows), said so, exit 1
{ cat tests/data/eval_tiny.txt; printf 'zz 0 1 0 1\n'; } >$T/bad-report.txt
run $E $tiny $T/bad-report.txt --report >$T/rep2.txt 2>$T/err.txt; rc=$?
if [ $rc -ne 0 ] && [ "$(awk '$1 == "rays" && NF == 2 { print $2 }' $T/rep2.txt)" = 6 ] &&
   grep -q "1 of 7 rows malformed (left out of the report)" $T/err.txt &&
   run $E $tiny $T/bad-report.txt --report --json 2>/dev/null |
     python3 -c 'import json,sys; sys.exit(json.load(sys.stdin)["warnings"] != ["1 of 7 rows malformed, left out of the report"])'
then ok eval_report_bad_row; else fail eval_report_bad_row "rc=$rc $(cat $T/err.txt)"; fi
# a test set of passing rays alone: false blocks are counted (x = 20 passes the lens,
# not the system), false passes cannot be
awk '/^#/ || $5 > 0' tests/data/eval_tiny.txt >$T/passing.txt
run $E $tiny $T/passing.txt --report >$T/rep3.txt 2>/dev/null
if [ "$(awk '$1 == "false_block" { print $2 }' $T/rep3.txt)" = 1 ] && ! grep -q '^false_pass ' $T/rep3.txt
then ok eval_report_passing_only; else fail eval_report_passing_only "$(grep -A8 'table: passage' $T/rep3.txt)"; fi
# an option of the other mode is an error, not ignored
expect_error eval_bins_without_report "--bins: only for the report" $E $tiny tests/data/eval_tiny.txt --bins 3
expect_error eval_raw_with_report "--raw: only for predictions" $E $tiny tests/data/eval_tiny.txt --raw --report
expect_error eval_report_with_emit "--report and --emit" $E $tiny --emit c --report
# a report compares outputs traced to the same place: a test set to the stop against a
# system of outer-pupil samples is refused (it had given errors of 11 mm without a word)
sed '/^pass /a meta trace_frame outer' $tiny >$T/outer.poly
{ echo '# frame: stop'; cat tests/data/eval_tiny.txt; } >$T/stop.txt
expect_error eval_report_frame "stop.txt: '# frame: stop': the test set was traced to the stop, the system's samples to the outer pupil" \
  $E $T/outer.poly $T/stop.txt --report
{ echo '# frame: outer'; cat tests/data/eval_tiny.txt; } >$T/outer.txt
if run $E $T/outer.poly $T/outer.txt --report >/dev/null 2>&1; then ok eval_report_same_frame; else fail eval_report_same_frame; fi
# no rays at all: the report says so, not that none is blocked
head -3 tests/data/eval_tiny.txt | grep '^#' >$T/header-only.txt
if run $E $tiny $T/header-only.txt --report 2>/dev/null | grep -q '^# passage not measured: the test set holds no ray$'
then ok eval_report_no_rays; else fail eval_report_no_rays; fi
expect_error eval_report_needs_reference "no reference column 'out_x'" \
  $E $tiny $T/bad.txt --report

# errors: FILE:LINE for a bad system, a missing column, a missing file; -o leaves nothing behind
printf 'lens-poly 1\ninputs x\noutputs a\nscaling x 0 1 nan 1\n' >$T/bad.poly
expect_error eval_bad_system "^lens-eval: .*bad.poly:4: domain minimum 'nan'" $E $T/bad.poly tests/data/eval_tiny.txt
printf '# columns: x z\n1 2\n' >$T/noy.txt
expect_error eval_missing_column "^lens-eval: .*'y'" $E $tiny $T/noy.txt
expect_error eval_missing_file "^lens-eval: .*nonexistent" $E $tiny $T/nonexistent.txt -o $T/o.txt
if [ ! -e $T/o.txt ] && ! ls $T | grep -q tmp; then ok eval_no_partial_output; else fail eval_no_partial_output "$(ls $T)"; fi
run $E $tiny tests/data/eval_tiny.txt -o $T/o.txt 2>/dev/null
if cmp -s $T/o.txt $T/pred.txt; then ok eval_output_file; else fail eval_output_file; fi
expect_error eval_unknown_option "unknown option" $E $tiny --frobnicate

# --emit c: the compiled function gives what lens-eval gives, on a two-part system
sys=tests/data/eval_parts.poly
awk 'BEGIN { srand(5); print "# columns: x y u v lambda";
             for (i = 0; i < 300; i++) printf "%.6f %.6f %.6f %.6f %.4f\n",
               36*rand()-18, 36*rand()-18, 1.2*rand()-0.6, 1.2*rand()-0.6, 0.4+0.3*rand() }' >$T/rays.txt
run $E $sys --emit c --name lens_fn -o $T/fn.c
CC=${CC:-cc}
# same_as_eval C E: the 300 rows of the compiled function (flag, 5 outputs) are
# lens-eval --raw's outputs (columns 12..16) to 1e-12 relative.
same_as_eval() {
  paste -d' ' "$1" "$2" | awk '{ for (k = 0; k < 5; k++) { c = $(2 + k); e = $(12 + k);
      d = c - e; if (d < 0) d = -d; s = e < 0 ? -e : e; if (s < 1e-300) s = 1;
      if (d > 1e-12 * s) { print "row " NR ": " c " vs " e; exit 1 } } }
      END { if (NR != 300) { print NR " rows"; exit 1 } }'
}
driver="tests/data/emitted_main.c -DLENS_FN=lens_fn"
if $CC -std=c99 -O2 -Wall -Werror $T/fn.c $driver -o $T/fn -lm; then
  $T/fn <$T/rays.txt >$T/c.txt
  run $E $sys $T/rays.txt --raw 2>/dev/null | grep -v '^#' >$T/e.txt
  if same_as_eval $T/c.txt $T/e.txt; then ok eval_emit_c_matches; else fail eval_emit_c_matches; fi
else
  fail eval_emit_c_matches "emitted C does not compile"
fi
expect_error eval_emit_bad_name "not a C identifier" $E $sys --emit c --name 9x
expect_error eval_emit_keyword_name "'int' cannot name the generated C: a C or C\+\+ keyword" $E $sys --emit c --name int

# The same for a system fitted by lens-fit to rays traced by lens-trace (the issue's
# check: emitted C against lens-eval on the same rays, to 1e-12 relative).
if [ -x $BIN/lens-trace ] && [ -x $BIN/lens-fit ]; then
  n=800 deg=6; [ -n "${SANITIZE:-}" ] && n=300 deg=4
  run $BIN/lens-trace lenses/fisheye-ii.lens -n $n --seed 1 >$T/train.txt 2>/dev/null &&
  run $BIN/lens-fit -q --terms 12 --degree $deg $T/train.txt -o $T/fit.poly &&
  run $BIN/lens-trace lenses/fisheye-ii.lens -n 300 --seed 2 >$T/test.txt 2>/dev/null &&
  run $E $T/fit.poly --emit c --name lens_fn -o $T/fit.c
  if [ -s $T/fit.c ] && $CC -std=c99 -O2 -Wall -Werror $T/fit.c $driver -o $T/fitfn -lm; then
    awk '/^#/ { next } { print $1, $2, $3, $4, $5 }' $T/test.txt | $T/fitfn >$T/c.txt
    run $E $T/fit.poly $T/test.txt --raw 2>/dev/null | grep -v '^#' >$T/e.txt
    if same_as_eval $T/c.txt $T/e.txt; then ok eval_emit_c_fitted; else fail eval_emit_c_fitted; fi
    # the report on a held-out set: finite, and positions within a millimetre
    run $E $T/fit.poly $T/test.txt --report >$T/frep.txt 2>/dev/null
    if awk '$1 == "out_x_mm" && NF == 7 { found = 1; if (!($3 + 0 == $3 && $3 > 0 && $3 < 1)) exit 1 } END { exit !found }' $T/frep.txt
    then ok eval_report_fitted; else fail eval_report_fitted "$(head -3 $T/frep.txt)"; fi
  else
    fail eval_emit_c_fitted "could not fit, emit or compile"
  fi
fi
