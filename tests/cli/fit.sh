#!/usr/bin/env bash
# lens-fit: a fisheye-ii fit checked on rays of another seed, determinism, the
# single-wavelength and output choices, C output, and every degenerate input.
source "$(dirname "$0")/lib.sh"
F=$BIN/lens-fit
TR=$BIN/lens-trace
E=$BIN/lens-eval

if run $F --help | grep -q '^usage: lens-fit'; then ok fit_help; else fail fit_help; fi

# fisheye-ii: fit a few thousand rays (seed 1), check on rays traced with seed 2.
# Under the sanitizers everything is 5-10x slower: a smaller, lower-degree fit.
if [ -n "${SANITIZE:-}" ]; then n=1500; opts="--terms 25 --degree 7"; else n=4000; opts=""; fi
run $TR lenses/fisheye-ii.lens -n $n --seed 1 -o $T/train.txt
run $TR lenses/fisheye-ii.lens -n 3000 --seed 2 -o $T/test.txt
if run $F $opts $T/train.txt -o $T/fe.poly 2>$T/fit.err; then ok fit_fisheye_runs
else fail fit_fisheye_runs "$(cat $T/fit.err)"; fi
# the summary names every output with its terms and held-out error
if [ "$(grep -c 'holdout_rms' $T/fit.err)" = 5 ] && grep -q 'fit time' $T/fit.err
then ok fit_summary; else fail fit_summary "$(cat $T/fit.err)"; fi
# outputs never nan inside the domain (--raw: also where the system says "blocked")
run $E $T/fe.poly $T/test.txt --raw >$T/pred.txt 2>/dev/null
if [ "$(grep -vc '^#' $T/pred.txt)" = 3000 ] && ! grep -v '^#' $T/pred.txt | grep -qiE 'nan|inf'
then ok fit_fisheye_finite; else fail fit_fisheye_finite "$(grep -ciE 'nan|inf' $T/pred.txt) non-finite"; fi
# The error on the new rays must match the fit's own held-out estimate (both estimate
# the same expected error; with ~800 held-out rays the estimate is good to ~10%, so
# allow 1.5x), and it must be small against the scale of the outputs: out_x spans
# about +-25 mm on this lens, and a usable system errs by well under 0.1 mm.
run $E $T/fe.poly $T/test.txt --report >$T/rep.txt 2>/dev/null
for o in out_x out_y; do
  rms=$(awk -v o=$o '$1 == o && $NF == "mm" && NF == 7 { print $3; exit }' $T/rep.txt)
  est=$(awk -v o="fit_$o" '$1 == "meta" && $2 == o { for (i = 3; i < NF; i++) if ($i == "holdout_rms") print $(i + 1) }' $T/fe.poly)
  if [ -n "$rms" ] && [ -n "$est" ] && awk -v r="$rms" -v e="$est" 'BEGIN { exit !(r <= 1.5 * e && r >= e / 1.5 && r < 0.1) }'
  then ok fit_fisheye_error_$o; else fail fit_fisheye_error_$o "test rms '$rms', held-out estimate '$est'"; fi
done

# deterministic: the same samples and flags give the same file with 1 or 2 threads
head -1500 $T/train.txt >$T/det.txt
run $F --terms 20 --degree 7 $T/det.txt --threads 1 -q -o $T/t1.poly
run $F --terms 20 --degree 7 $T/det.txt --threads 2 -q -o $T/t2.poly
if cmp -s $T/t1.poly $T/t2.poly; then ok fit_deterministic
else fail fit_deterministic "files differ"; fi

# single wavelength: lambda left out of the inputs; a file of one wavelength is accepted
# and recorded, a file of several is refused (a system without lambda cannot follow
# dispersion)
run $TR lenses/fisheye-ii.lens -n 800 --seed 3 --lambda 0.55 -o $T/mono.txt
if run $F --terms 15 --degree 5 --inputs x,y,u,v -q $T/mono.txt -o $T/mono.poly &&
   grep -q '^inputs x y u v$' $T/mono.poly && grep -q '^meta lambda 0.55' $T/mono.poly
then ok fit_single_wavelength; else fail fit_single_wavelength "$(grep -E '^(inputs|meta lambda)' $T/mono.poly)"; fi
expect_error fit_mixed_wavelengths 'lambda .* differs .* not among --inputs' \
  $F --terms 15 --degree 5 --inputs x,y,u,v -q $T/train.txt
# a constant lambda as an input is a constant column
expect_error fit_constant_column 'input lambda is constant' $F --terms 15 --degree 5 -q $T/mono.txt

# --outputs: only those outputs are fitted
if run $F --terms 15 --degree 5 --outputs out_x,out_y -q $T/mono.txt --inputs x,y,u,v -o $T/xy.poly &&
   grep -q '^outputs out_x out_y$' $T/xy.poly && grep -q '^pass out_x out_y ' $T/xy.poly
then ok fit_outputs; else fail fit_outputs "$(grep -E '^(outputs|pass)' $T/xy.poly)"; fi

# parts: a tolerance one polynomial of 8 terms cannot meet makes lens-fit cut the
# sensor into rings; the file says how many and the largest jump between them
if run $F --terms 8 --degree 5 --inputs x,y,u,v --outputs out_x,out_y --tolerance out_x=1e-5 \
     --parts 2 $T/mono.txt -o $T/parts.poly 2>$T/parts.err &&
   grep -q '^meta fit_parts 2$' $T/parts.poly && grep -q '^meta part_jump_out_x ' $T/parts.poly &&
   grep -q 'largest_part_jump' $T/parts.err
then ok fit_parts; else fail fit_parts "$(grep -E '^meta' $T/parts.poly) $(cat $T/parts.err)"; fi

# --emit c: a C function that compiles as is
if run $F --terms 15 --degree 5 --inputs x,y,u,v -q $T/mono.txt --emit c --name fe_eval -o $T/fe.c &&
   cc -std=c99 -Wall -c $T/fe.c -o $T/fe.o 2>$T/cc.err && grep -q 'fe_eval' $T/fe.c
then ok fit_emit_c; else fail fit_emit_c "$(head -3 $T/cc.err)"; fi

# degenerate input: one-line errors naming the problem, and no output file left behind
printf '# columns: x y u v lambda out_x out_y out_u out_v out_eta\n' >$T/empty.txt
expect_error fit_empty 'no samples' $F -q $T/empty.txt
: >$T/nothing.txt
expect_error fit_empty_file 'nothing.txt' $F -q $T/nothing.txt
{ head -30 $T/train.txt; echo '1 nan 0.1 0.1 0.5 1 1 0.1 0.1 0.3'; } >$T/nan.txt
expect_error fit_nan_input 'nan.txt:31: input y is nan' $F -q $T/nan.txt
head -40 $T/train.txt >$T/few.txt
expect_error fit_too_few 'fewer than the 40 terms' $F -q $T/few.txt -o $T/few.poly
if [ ! -e $T/few.poly ] && [ -z "$(ls $T | grep -E '^few\.poly.')" ]; then ok fit_no_partial_file
else fail fit_no_partial_file "$(ls $T)"; fi
expect_error fit_missing_column "no column 'w'" $F -q --inputs x,y,w $T/train.txt
expect_error fit_bad_option 'unknown option' $F --frobnicate $T/train.txt
expect_error fit_bad_terms '--terms' $F --terms 0 $T/train.txt
# every ray blocked
awk '/^#/ { print; next } { $6 = "nan"; $10 = 0; print }' $T/few.txt >$T/blocked.txt
expect_error fit_all_blocked 'every ray is blocked' $F -q $T/blocked.txt
