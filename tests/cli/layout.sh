#!/usr/bin/env bash
# The flow of the stages: no include may point up it; a file of a stage
# includes headers of its own stage and of the stages before it only. The include order
# is base < lens < trace < sample < poly < fit < analysis, render < app < cmd: rays flow
# sample -> fit -> poly, but the fitter builds its result through the polynomial model
# (poly.h: systems, frames, transforms), so in the code poly comes before fit (poly never
# includes fit). A public header
# (include/sparselens/X.h) belongs to the stage of src/<stage>/X.c (or .cpp), else to
# the lowest stage of a source file that includes it first (its own header); a header
# that neither places is an error (name it after its .c). Internal headers belong to
# their folder. analysis and render are siblings: neither may include the other.
source "$(dirname "$0")/lib.sh"

awk -v top="$TOP" '
BEGIN {
  n = split("base lens trace sample poly fit analysis render app", order, " ")
  for (i = 1; i <= n; i++) rank[order[i]] = i
  rank["render"] = rank["analysis"]; rank["app"] = 8; rank["cmd"] = 9
  # sources: stage of every src/<stage>/<name>.c and of first includes
  cmd = "cd " top " && ls src/*/*.c src/*/*.cpp 2>/dev/null"
  while ((cmd | getline f) > 0) {
    split(f, p, "/"); st = p[2]; name = p[3]; sub(/\.(c|cpp)$/, "", name)
    home[name ".h"] = st
    srcs[++ns] = f
  }
  close(cmd)
  for (k = 1; k <= ns; k++) {
    f = srcs[k]; split(f, p, "/"); st = p[2]
    while ((getline line < (top "/" f)) > 0)
      if (match(line, /^#include "sparselens\/[A-Za-z0-9_]+\.h"/)) {
        h = substr(line, 22, RLENGTH - 22)
        if (!(h in first) || rank[st] < rank[first[h]]) first[h] = st
        break
      }
    close(top "/" f)
  }
  # Exceptions, each with its reason ("FILE INCLUDE"): none.
  bad = 0
  cmd = "cd " top " && ls include/sparselens/*.h"
  while ((cmd | getline f) > 0) {
    h = f; sub(/.*\//, "", h)
    if (h in home) stage[h] = home[h]
    else if (h in first) stage[h] = first[h]
    else { print "FAIL layout: cannot place include/sparselens/" h " in a stage (no src/*/" substr(h, 1, length(h) - 2) ".c, and no source includes it first)"; bad++ }
  }
  close(cmd)
  # every include of every file
  cmd = "cd " top " && ls src/*/*.c src/*/*.cpp src/*/*.h include/sparselens/*.h cmd/*.c 2>/dev/null"
  checked = 0
  while ((cmd | getline f) > 0) {
    split(f, p, "/")
    if (p[1] == "cmd") st = "cmd"
    else if (p[1] == "src") st = p[2]
    else { h = p[3]; st = stage[h] }
    if (st == "") continue
    ln = 0
    while ((getline line < (top "/" f)) > 0) {
      ln++
      if (!match(line, /^#include "[A-Za-z0-9_\/]+\.h"/)) continue
      inc = substr(line, 11, RLENGTH - 11)
      if (inc ~ /^sparselens\//) { h = substr(inc, 12); to = stage[h] }
      else { split(inc, q, "/"); to = q[1] }
      if (!(to in rank)) continue
      checked++
      if (allowed[f " " inc]) continue
      if (rank[to] > rank[st] || (rank[to] == rank[st] && to != st && st != "cmd")) {
        printf "FAIL layout: %s:%d: %s (%s) includes %s (%s), up the flow\n", f, ln, f, st, inc, to
        bad++
      }
    }
    close(top "/" f)
  }
  close(cmd)
  if (bad == 0) printf "ok layout (%d includes follow the flow)\n", checked
}'

# The size check itself, on a made-up checkout: a function of 121 lines and a file of 601
# are offenders, 120 and 600 are not, and a written reason excuses either.
mk() { # FILE FUNCTION-LINES FILE-LINES [REASON-LINE]: a function of that many lines, the
       # file padded to its lines
  { if [ -n "${4:-}" ]; then echo "$4"; fi
    echo 'static int f(void)'; echo '{'; yes '    x++;' | head -n $(($2 - 3)); echo '}'; } >"$1"
  yes '/* */' | head -n $(($3 - $(wc -l <"$1"))) >>"$1"
}
mkdir -p "$T/house/src" && git -C "$T/house" init -q
mk "$T/house/src/a.c" 121 130; mk "$T/house/src/b.c" 120 601; mk "$T/house/src/c.c" 120 600
mk "$T/house/src/d.c" 121 601 '/* Long file: and a Long function: both for the test */'
git -C "$T/house" add -A
got=$(tools/house-check.sh --list "$T/house" | sed 's/: .*//' | tr '\n' ' ')
if [ "$got" = "src/a.c:1 src/b.c:1 " ]; then ok house_check_finds_offenders
else fail house_check_finds_offenders "listed '$got', expected 'src/a.c:1 src/b.c:1 '"; fi

# Sizes (tools/house-check.sh): no function over 120 lines and no file over 600 without a
# reason written beside it.
if offenders=$(tools/house-check.sh); then ok house_check
else fail house_check "$(tr '\n' ';' <<<"$offenders")"; fi
