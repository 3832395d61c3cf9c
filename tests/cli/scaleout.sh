#!/usr/bin/env bash
# The README's scale-out block, taken from the README itself and run locally through GNU
# parallel (":" is this machine in --sshlogin; smaller counts), gives exactly what a
# sequential run gives: the fitted systems, and the traced and evaluated ray files whole,
# header lines included.
. "$(dirname "$0")/lib.sh"
command -v parallel >/dev/null || { ok "scaleout (skipped: GNU parallel missing)"; exit 0; }
for c in lens-trace lens-fit lens-eval; do [ -x "$BIN/$c" ] || { ok "scaleout (skipped: $c)"; exit 0; }; done
export PATH="$TOP/$BIN:$PATH"
n=2000; [ -n "$SANITIZE" ] && n=600
lenses="lenses/dgauss.50mm.lens lenses/simple.lens lenses/petzval.lens"

# The block, with local hosts and small counts; each substitution must apply, so a
# change of the README's example shows here.
block=$(awk '/^## Scale-out/ { s = 1 } s && /^```sh/ { b = 1; next } b && /^```/ { exit } b' README.md)
subs=(
  "ls lenses/\*\.lens|printf '%s\\\\n' $lenses"
  "--sshlogin 2/host1,2/host2,:|-j 2 --sshlogin :"
  "--sshlogin host1,host2|--sshlogin :"
  "-n 15000|-n $n"
  "-n 1000000|-n $((n * 3))"
  "-N 100000|-N 500"
)
for s in "${subs[@]}"; do
  from=${s%%|*} to=${s#*|}
  if ! grep -qe "$from" <<<"$block"; then fail "README scale-out block" "no '$from' in it: update tests/cli/scaleout.sh"; exit 0; fi
  block=$(sed "s#$from#$to#" <<<"$block")
done
mkdir -p "$T/par" "$T/seq"
cp -r lenses "$T/par/"
( cd "$T/par" && bash -o pipefail -c "$block" ) >"$T/par.log" 2>&1 ||
  { fail "README scale-out block runs" "$(tail -3 "$T/par.log" | tr '\n' ' ')"; exit 0; }
ok "README scale-out block runs"

# (the sequential run in the same layout: a system records its lens path as given)
cp -r lenses "$T/seq/"
for l in $lenses; do
  b=$(basename "$l" .lens)
  (cd "$T/seq" && lens-trace "$l" -n $n --seed 1 | lens-fit -q --lens "$b" -o "$b.poly")
  if cmp -s "$T/par/$b.poly" "$T/seq/$b.poly"; then ok "parallel fit $b = sequential"
  else fail "parallel fit $b = sequential" "$(cat "$T/par.log")"; fi
done

lens-trace lenses/dgauss.50mm.lens - < "$T/par/rays.txt" > "$T/seq/traced.txt"
if [ "$(grep -vc '^#' "$T/seq/traced.txt")" -eq $((n * 3)) ] && cmp -s "$T/par/traced.txt" "$T/seq/traced.txt"; then
  ok "parallel --pipe trace = sequential, whole file ($(wc -l < "$T/seq/traced.txt") lines)"
else fail "parallel --pipe trace = sequential" "$(wc -l "$T/par/traced.txt" "$T/seq/traced.txt" | head -2 | tr '\n' ' ')"; fi

# The same pipeline for lens-eval ("trace (or evaluate)").
sys=$T/seq/dgauss.50mm.poly
parallel --will-cite --pipe --keep-order -N 500 --header '(#.*\n)*' \
  lens-eval "$sys" - < "$T/par/rays.txt" 2>/dev/null | awk '!/^#/ || !seen[$0]++' > "$T/epar.txt"
lens-eval "$sys" - < "$T/par/rays.txt" 2>/dev/null > "$T/eseq.txt"
if [ -s "$T/eseq.txt" ] && cmp -s "$T/epar.txt" "$T/eseq.txt"; then ok "parallel --pipe eval = sequential, whole file"
else fail "parallel --pipe eval = sequential" "$(wc -l "$T/epar.txt" "$T/eseq.txt" | head -2 | tr '\n' ' ')"; fi
exit 0
