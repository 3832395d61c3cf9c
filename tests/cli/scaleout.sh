#!/usr/bin/env bash
# The README's scale-out examples, run locally through GNU parallel (":" is this
# machine in --sshlogin), give exactly what a sequential run gives.
. "$(dirname "$0")/lib.sh"
command -v parallel >/dev/null || { ok "scaleout (skipped: GNU parallel missing)"; exit 0; }
for c in lens-trace lens-fit lens-eval; do [ -x "$BIN/$c" ] || { ok "scaleout (skipped: $c)"; exit 0; }; done
export PATH="$TOP/$BIN:$PATH"
n=2000; [ -n "$SANITIZE" ] && n=600
lenses="lenses/dgauss.50mm.lens lenses/simple.lens lenses/petzval.lens"

# 1. Fitting many lenses: one job per lens, the lens file sent to the host and the
#    system brought back (README, "Scale-out").
mkdir -p "$T/par" "$T/seq"
( cd "$T/par" && cp -r "$TOP/lenses" . &&
  printf '%s\n' $lenses | parallel --will-cite -j 2 --sshlogin : --transfer --return '{/.}.poly' --cleanup \
    "lens-trace {} -n $n --seed 1 | lens-fit -q --lens {/.} -o {/.}.poly" ) > "$T/par.log" 2>&1
# (the sequential run in the same layout: a system records its lens path as given)
cp -r "$TOP/lenses" "$T/seq/"
for l in $lenses; do
  b=$(basename "$l" .lens)
  (cd "$T/seq" && lens-trace "$l" -n $n --seed 1 | lens-fit -q --lens "$b" -o "$b.poly")
  if cmp -s "$T/par/$b.poly" "$T/seq/$b.poly"; then ok "parallel fit $b = sequential"
  else fail "parallel fit $b = sequential" "$(cat "$T/par.log")"; fi
done

# 2. A large ray file split into chunks (each with the header lines), traced and
#    evaluated in parallel, order kept: the same rows as one sequential run.
lens-trace lenses/dgauss.50mm.lens -n $((n * 3)) --all --seed 7 |
  awk '/^# columns:/ { print "# columns: x y u v lambda"; next } /^#/ { next } { print $1, $2, $3, $4, $5 }' > "$T/rays.txt"
parallel --will-cite --pipe --keep-order -N 500 --header '(#.*\n)*' \
  lens-trace lenses/dgauss.50mm.lens - < "$T/rays.txt" | grep -v '^#' > "$T/par.txt"
lens-trace lenses/dgauss.50mm.lens - < "$T/rays.txt" | grep -v '^#' > "$T/seq.txt"
if [ -s "$T/seq.txt" ] && cmp -s "$T/par.txt" "$T/seq.txt"; then ok "parallel --pipe trace = sequential ($(wc -l < "$T/seq.txt") rows)"
else fail "parallel --pipe trace = sequential" "$(wc -l "$T/par.txt" "$T/seq.txt")"; fi
parallel --will-cite --pipe --keep-order -N 500 --header '(#.*\n)*' \
  lens-eval "$T/seq/dgauss.50mm.poly" - < "$T/rays.txt" 2>/dev/null | grep -v '^#' > "$T/epar.txt"
lens-eval "$T/seq/dgauss.50mm.poly" - < "$T/rays.txt" 2>/dev/null | grep -v '^#' > "$T/eseq.txt"
if [ -s "$T/eseq.txt" ] && cmp -s "$T/epar.txt" "$T/eseq.txt"; then ok "parallel --pipe eval = sequential"
else fail "parallel --pipe eval = sequential" "$(wc -l "$T/epar.txt" "$T/eseq.txt")"; fi
exit 0
