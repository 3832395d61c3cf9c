# Shared helpers for command-line tests (sourced). Each check prints "ok NAME" or
# "FAIL NAME: why"; tests/run-tests.sh counts those lines.
set -u
BIN=${BIN:-bin}
BUILD=${BUILD:-build}
SANITIZE=${SANITIZE:-}
TOP=${TOP:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
cd "$TOP"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
# Under sanitizers the command-line tests are slow; VALGRIND=1 wraps commands in valgrind.
run() { if [ -n "${VALGRIND:-}" ]; then valgrind -q --error-exitcode=99 "$@"; else "$@"; fi; }
ok()   { echo "ok $1"; }
fail() { echo "FAIL $1: ${2:-}"; }
# check NAME CMD...: the command must succeed.
check() { local n=$1; shift; if "$@"; then ok "$n"; else fail "$n" "command failed: $*"; fi; }
# near A B TOL: |A - B| <= TOL
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }
# expect_error NAME PATTERN CMD...: must exit non-zero with a one-line stderr matching PATTERN.
expect_error() {
  local n=$1 pat=$2; shift 2
  local err rc
  err=$("$@" 2>&1 >/dev/null); rc=$?
  if [ $rc -eq 0 ]; then fail "$n" "exit 0, expected an error"; return; fi
  if ! grep -qE -- "$pat" <<<"$err"; then fail "$n" "stderr '$err' does not match '$pat'"; return; fi
  ok "$n"
}
# err_one NAME PATTERN CMD...: non-zero exit, no crash (signal or sanitizer report), and
# stderr one line matching PATTERN.
err_one() {
  local n=$1 pat=$2; shift 2
  local err rc
  err=$(run "$@" 2>&1 >/dev/null); rc=$?
  if [ $rc -eq 0 ]; then fail "$n" "exit 0"; return; fi
  if [ $rc -gt 128 ] || grep -qE 'Sanitizer|runtime error' <<<"$err"; then fail "$n" "crashed: $err"; return; fi
  if [ "$(grep -c '' <<<"$err")" -ne 1 ] || ! grep -qE -- "$pat" <<<"$err"; then
    fail "$n" "stderr '$err' does not match '$pat'"; return; fi
  ok "$n"
}
# makevar NAME: a variable of the Makefile (the library flags pkg-config found), for
# tests that build a driver themselves. The outer make's job server is not passed on.
makevar() { env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL "${MAKE:-make}" -s --no-print-directory -C "$TOP" "print-$1"; }
# value KEY < key-value lines
value() { awk -v k="$1" '$1 == k { print $2; exit }'; }
# passage_errors SYSTEM RAYS: "false_pass false_block" of lens-eval --report for the
# system on the rays (0 0 when the report has none).
passage_errors() {
  run "$BIN/lens-eval" "$1" --report <"$2" 2>/dev/null |
    awk '$1 == "false_pass" { p = $2 } $1 == "false_block" { b = $2 } END { print p + 0, b + 0 }'
}
