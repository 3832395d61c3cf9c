#!/usr/bin/env bash
# Hard cases of the fitter (tests/hard/hard_fit.c says each expectation). Built here
# against the library rather than by the Makefile's unit-test rule, so that it waits for
# fit_system to be in liblens without breaking the build before. Under SANITIZE the
# driver is built with the same sanitizers and uses fewer samples.
source "$(dirname "$0")/../cli/lib.sh"
BUILD=${BUILD:-build}
LIB=$BUILD/liblens.a
if [ ! -f "$LIB" ] || ! nm "$LIB" 2>/dev/null | grep -q ' T fit_system$'; then
  ok "hard_fit (skipped: fit_system not in $LIB on this branch)"; exit 0; fi
flags="-std=c11 -O2 -g -fopenmp $(makevar ARCH_FLAGS) $(makevar CPPFLAGS)"
[ -n "${SANITIZE:-}" ] && flags="$flags -O1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined"
libs=$(makevar LDLIBS)
# shellcheck disable=SC2086
if ! ${CC:-cc} $flags tests/hard/hard_fit.c "$LIB" $libs -o "$T/hard_fit" 2>"$T/cc.log"; then
  fail hard_fit_build "$(head -5 "$T/cc.log" | tr '\n' ' ')"; exit 0; fi
args=()
[ -n "${SANITIZE:-}" ] && args=(--small)
"$T/hard_fit" "${args[@]}"
rc=$?
[ $rc -eq 0 ] || [ $rc -eq 1 ] || fail hard_fit "driver exited with status $rc"
exit 0
