#!/usr/bin/env bash
# Filters carry the columns they do not know to their output, as GeodSolve and cs2cs pass
# the rest of a line: lens-trace - and lens-eval keep an id column (text or number), the
# rows stay aligned across lens-eval's 4096-row chunks, and the traced or predicted
# values are those of the same run without the extra columns.
source "$(dirname "$0")/lib.sh"
L=lenses/dgauss.50mm.lens

# 5000 rays (more than one lens-eval chunk), an id before and a tag after the inputs
# (no passage columns: the traced columns are then the ten of the header checks below)
run $BIN/lens-trace $L -n 5000 --seed 3 --no-passage-columns -o $T/rays.txt
awk '/^# columns:/ { print "# columns: id x y u v lambda tag"; next } /^#/ { next }
     { n++; print "r" n, $1, $2, $3, $4, $5, (n % 2 ? "odd" : "even") }' $T/rays.txt >$T/in.txt
grep -v '^#' $T/rays.txt | awk '{ print $1, $2, $3, $4, $5 }' | sed '1i # columns: x y u v lambda' >$T/plain.txt

run $BIN/lens-trace $L - --no-passage-columns <$T/in.txt >$T/traced.txt 2>$T/err.txt; rc=$?
run $BIN/lens-trace $L - --no-passage-columns <$T/plain.txt >$T/traced_plain.txt
if [ $rc -eq 0 ] && grep -q '^# columns: x y u v lambda out_x out_y out_u out_v out_eta id tag$' $T/traced.txt &&
   diff <(grep -v '^#' $T/traced.txt | awk '{ $NF = ""; $(NF-1) = ""; print }' | sed 's/ *$//') \
        <(grep -v '^#' $T/traced_plain.txt) >/dev/null &&
   awk '!/^#/ { n++; if ($11 != "r" n || $12 != (n % 2 ? "odd" : "even")) bad = 1 } END { exit bad || n != 5000 }' $T/traced.txt
then ok trace_passthrough; else fail trace_passthrough "rc=$rc $(head -3 $T/traced.txt) $(cat $T/err.txt)"; fi

run $BIN/lens-fit -q --terms 20 -o $T/d.poly $T/rays.txt 2>/dev/null
run $BIN/lens-eval $T/d.poly $T/traced.txt >$T/pred.txt 2>$T/err.txt; rc=$?
run $BIN/lens-eval $T/d.poly $T/plain.txt >$T/pred_plain.txt 2>/dev/null
if [ $rc -eq 0 ] && grep -q '^# columns: x y u v lambda out_x out_y out_u out_v out_eta id tag$' $T/pred.txt &&
   diff <(grep -v '^#' $T/pred.txt | awk '{ $NF = ""; $(NF-1) = ""; print }' | sed 's/ *$//') \
        <(grep -v '^#' $T/pred_plain.txt) >/dev/null &&
   awk '!/^#/ { n++; if ($11 != "r" n || $12 != (n % 2 ? "odd" : "even")) bad = 1 } END { exit bad || n != 5000 }' $T/pred.txt
then ok eval_passthrough; else fail eval_passthrough "rc=$rc $(head -3 $T/pred.txt) $(cat $T/err.txt)"; fi

# a bad row keeps its id beside the row of nan; a short row gets nan in the id's place
printf '# columns: x y u v lambda id\n0 0 0 0 0.55 a\n0 x 0 0 0.55 b\n0 0 0\n' >$T/bad.txt
run $BIN/lens-trace $L - --no-passage-columns <$T/bad.txt >$T/bad_out.txt 2>/dev/null; rc=$?
if [ $rc -ne 0 ] && [ "$(grep -v '^#' $T/bad_out.txt | awk '{ print $NF }' | tr '\n' ' ')" = "a b nan " ] &&
   [ "$(grep -v "^#" $T/bad_out.txt | sed -n 3p | awk '{ print $1, $10 }')" = "nan nan" ]
then ok trace_passthrough_bad_rows; else fail trace_passthrough_bad_rows "$(cat $T/bad_out.txt)"; fi
run $BIN/lens-eval $T/d.poly $T/bad.txt >$T/bad_eval.txt 2>/dev/null; rc=$?
if [ $rc -ne 0 ] && [ "$(grep -v '^#' $T/bad_eval.txt | awk '{ print $NF }' | tr '\n' ' ')" = "a b nan " ]
then ok eval_passthrough_bad_rows; else fail eval_passthrough_bad_rows "$(cat $T/bad_eval.txt)"; fi
