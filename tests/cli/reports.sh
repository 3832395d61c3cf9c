#!/usr/bin/env bash
# A reduced `make reports` (two lenses, a few points) and the consistency of its
# numbers: training error against terms, the Pareto table, traceability of figures.
. "$(dirname "$0")/lib.sh"
for c in lens-trace lens-fit lens-eval lens-spot lens-distort; do
  [ -x "$BIN/$c" ] || { ok "reports (skipped: $c not built)"; exit 0; }
done
command -v gnuplot >/dev/null || { ok "reports (skipped: no gnuplot)"; exit 0; }
if make -s -f tools/reports.mk BIN="$BIN" BUILD="$BUILD" LENSES="simple dgauss.50mm" MODE=reduced OUT="$T/r" \
     > "$T/log" 2>&1; then ok "reduced reports run"; else fail "reduced reports run" "$(tail -5 "$T/log")"; exit 0; fi
for f in accuracy-vs-time.md simple.md dgauss.50mm.md accuracy/simple-pareto.png lenses/dgauss.50mm-spot.png; do
  [ -s "$T/r/$f" ] && ok "wrote $f" || fail "wrote $f" "missing"
done
python3 tools/check_report.py "$T/r"
# A second run reuses every result: nothing is swept again.
make -s -f tools/reports.mk BIN="$BIN" BUILD="$BUILD" LENSES="simple dgauss.50mm" MODE=reduced OUT="$T/r" > "$T/log2" 2>&1
grep -q 'sweeping' "$T/log2" && fail "reuse" "swept again: $(cat "$T/log2")" || ok "second run reuses the sweeps"
exit 0
