#!/bin/sh
# man-options.sh PAGE COMMAND: replaces the OPTIONS section of the man page PAGE (from
# its ".SH OPTIONS" line to the next ".SH") with `COMMAND --help-man`, generated from
# the command's option table; PAGE is rewritten only when that changes it. `make` runs
# this for every command (target `man`), so an option is documented where it is defined.
set -eu
page=$1 cmd=$2
tmp=$(mktemp "${TMPDIR:-/tmp}/man-options.XXXXXX")
gen=$(mktemp "${TMPDIR:-/tmp}/man-options.XXXXXX")
trap 'rm -f "$tmp" "$gen"' EXIT
"$cmd" --help-man >"$gen"
grep -q '^\.SH OPTIONS' "$page" || { echo "$0: $page has no .SH OPTIONS section" >&2; exit 1; }
awk -v gen="$gen" '
  skip && /^\.SH / { skip = 0 }
  skip { next }
  { print }
  /^\.SH OPTIONS/ { while ((getline line < gen) > 0) print line; skip = 1 }
' "$page" >"$tmp"
cmp -s "$tmp" "$page" || cat "$tmp" >"$page"
