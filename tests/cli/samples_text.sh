#!/usr/bin/env bash
# The numbers sample files hold, written by a library's digits, are printf's bytes for
# the rule the format states (%.15g when it reads back, else %.17g): every lens's default
# samples checked number by number against Python's printf-style formatting.
source "$(dirname "$0")/lib.sh"
if ! command -v python3 >/dev/null; then echo "ok samples_text_printf # skip: no python3"; exit 0; fi
for f in lenses/*.lens lenses/*.zmx lenses/*.seq; do
  n=$(basename "$f") sensor=()
  case $f in *.zmx|*.seq) sensor=(--sensor 24x24) ;; esac # design files name no sensor
  run "$BIN/lens-trace" "$f" "${sensor[@]}" -n 300 --seed 2 >"$T/$n.txt" 2>/dev/null || { fail "samples_text_$n" "lens-trace failed"; continue; }
  why=$(python3 - "$T/$n.txt" <<'PY'
import sys
def ref(t):
    v = float(t)
    if v != v: return "nan"
    if v in (float("inf"), float("-inf")): return "inf" if v > 0 else "-inf"
    s = "%.15g" % v
    return s if float(s) == v else "%.17g" % v
bad = [t for line in open(sys.argv[1]) if not line.startswith("#") for t in line.split() if ref(t) != t]
rows = sum(1 for line in open(sys.argv[1]) if not line.startswith("#"))
print("no rows" if rows == 0 else ("%d of the numbers differ, e.g. %s -> %s" % (len(bad), bad[0], ref(bad[0])) if bad else ""))
PY
)
  if [ -z "$why" ]; then ok "samples_text_$n"; else fail "samples_text_$n" "$why"; fi
done
