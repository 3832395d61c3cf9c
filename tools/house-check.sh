#!/usr/bin/env bash
# house-check.sh [--list] [DIR]: the house rules on size that a reader can check by
# counting. A C or C++ function over 120 lines (from the first line of its signature to
# its closing brace) and a source file over 600 lines are offenders, each printed as
# "FILE:LINE: what", unless a reason is written down: a comment line with "Long file:"
# and why in the file's first 20 lines, or with "Long function:" and why in the 10 lines
# above the function. Exit 1 when there is an offender; with --list, print them, exit 0.
# Functions are found by the project's layout: the signature starts in column 0, the body
# opens with "{" alone in column 0 and closes with the next "}" in column 0.
# DIR (default: this repository) is a git checkout; its tracked files are read.
set -u
list=0
[ "${1:-}" = --list ] && { list=1; shift; }
cd "${1:-$(dirname "$0")/..}" || exit 2
max_function=120 max_file=600

offenders=$(git ls-files -- src include cmd tests bench tools |
  grep -E '\.(c|h|cpp|sh|py|mk)$' | while IFS= read -r f; do
  [ -f "$f" ] || continue
  awk -v f="$f" -v maxfn=$max_function -v maxfile=$max_file '
    FNR <= 20 && /Long file:/ { reason = 1 }
    /Long function:/ { why_line = FNR }
    /^[A-Za-z_]/ && !/^\{/ { head = $0; head_line = FNR }
    f ~ /\.(c|h|cpp)$/ && /^\{[ \t]*$/ { open = head_line; name = head
      excused = why_line && why_line < open && why_line >= open - 10
      if (match(name, /[A-Za-z_][A-Za-z0-9_:]*[ \t]*\(/)) name = substr(name, RSTART, RLENGTH - 1)
      sub(/[ \t]+$/, "", name) }
    open && /^\}/ { n = FNR - open + 1
      if (n > maxfn && !excused) printf "%s:%d: function %s is %d lines (at most %d)\n", f, open, name, n, maxfn
      open = 0 }
    END { if (FNR > maxfile && !reason)
            printf "%s:1: %d lines (at most %d without a \"Long file:\" reason in its first 20 lines)\n", f, FNR, maxfile }
  ' "$f"
done)

[ -n "$offenders" ] && printf '%s\n' "$offenders"
[ -z "$offenders" ] || [ $list = 1 ]
