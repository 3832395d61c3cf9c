#!/bin/sh
# man-options.sh PAGE COMMAND: replaces the sections of the man page PAGE that
# `COMMAND --help-man` prints (SYNOPSIS and OPTIONS, generated from the command's option
# table), each from its ".SH" line to the next ".SH"; PAGE is rewritten only when that
# changes it. `make` runs this for every command (target `man`), so an option is
# documented where it is defined; tests/cli/man_options.sh runs it on a copy of each page
# and fails when the copy changes.
set -eu
page=$1 cmd=$2
tmp=$(mktemp "${TMPDIR:-/tmp}/man-options.XXXXXX")
gen=$(mktemp "${TMPDIR:-/tmp}/man-options.XXXXXX")
trap 'rm -f "$tmp" "$gen"' EXIT
"$cmd" --help-man >"$gen"
grep '^\.SH ' "$gen" | while IFS= read -r section; do
  grep -qxF "$section" "$page" || { echo "$0: $page has no '$section' section" >&2; exit 1; }
done
awk -v gen="$gen" '
  BEGIN {
    while ((getline line < gen) > 0) {
      if (line ~ /^\.SH /) { name = line; order[++n] = name }
      else body[name] = body[name] line "\n"
    }
  }
  skip && /^\.SH / { skip = 0 }
  skip { next }
  { print }
  /^\.SH / && ($0 in body) { printf "%s", body[$0]; skip = 1 }
' "$page" >"$tmp"
cmp -s "$tmp" "$page" || cat "$tmp" >"$page"
