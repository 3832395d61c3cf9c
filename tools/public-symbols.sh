#!/usr/bin/env bash
# tools/public-symbols.sh CC HEADER: the names of the functions and variables the public
# headers (HEADER and the sparselens/ headers it includes) declare, one a line: what
# libsparselens.so exports (the Makefile makes its version script from them, and
# tests/cli/library.sh checks the library against them). Functions come from the
# compiler's own list of the prototypes it saw (-aux-info), variables from the headers'
# `extern` lines.
set -euo pipefail
cc=$1 header=$2
inc=$(dirname "$header")
aux=$(mktemp)
trap 'rm -f "$aux"' EXIT
$cc -I"$inc" -x c -std=c11 -fsyntax-only -aux-info "$aux" "$header"
{
  # "/* include/sparselens/lens.h:73:NC */ extern int lens_load (const char *, ...);"
  awk '$2 ~ /sparselens/ && / extern / {
         sub(/^.*\*\/ /, ""); s = substr($0, 1, index($0, " (") - 1)
         n = split(s, w, /[ *]+/); print w[n] }' "$aux"
  headers=$(grep -o '"sparselens/[a-z_]*\.h"' "$header" | tr -d '"' | sed "s#^#$inc/#")
  # shellcheck disable=SC2086
  sed -n 's/^extern [^(]*[ *]\([a-z_][a-z0-9_]*\);.*/\1/p' $headers
} | sort -u
