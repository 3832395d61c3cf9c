#!/usr/bin/env bash
# Hostile input: what an adversarial user tries, each answered by a clean
# one-line error or by the right result, never by a crash, a silent cut or lost data.
# Kept fast: small files, except where a size is the point (then a few MB at most).
source "$(dirname "$0")/lib.sh"

# A Zemax NAME after 250 blanks once read past a 256-byte copy of its line: the name
# must be the file's text (shortened with "..." and a note), not stack bytes.
reg=tests/fuzz/regressions/zmx/name-after-250-blanks.zmx
out=$(run "$BIN/lens-info" --format lens "$reg" 2>"$T/err")
name=$(sed -n 's/^# name: //p' <<<"$out")
if [[ $name == "Long Long Long "*"..." ]] && [ ${#name} -le 127 ] &&
   grep -q 'name shortened from 300 characters' <<<"$out"; then ok zmx_long_indented_name
else fail zmx_long_indented_name "name '$name'"; fi

# ---- readers: bounded lines, read errors, NUL bytes, byte-order marks ----------------
LENS=lenses/simple.lens
# A read error (here: a directory where a file is expected) is an error, never an end.
mkdir -p "$T/dir.lens"
err_one read_error_lens 'dir.lens: a directory, not a file to read' "$BIN/lens-info" "$T/dir.lens"
err_one read_error_fit '<stdin>: read error' "$BIN/lens-fit" --terms 3 <"$T/dir.lens"
err_one read_error_trace '<stdin>: read error' "$BIN/lens-trace" "$LENS" - <"$T/dir.lens"
"$BIN/lens-trace" "$LENS" -n 200 --seed 1 >"$T/s.txt" 2>/dev/null
"$BIN/lens-fit" --terms 4 --degree 3 <"$T/s.txt" >"$T/s.poly" 2>/dev/null
err_one read_error_eval 'read error' "$BIN/lens-eval" "$T/s.poly" <"$T/dir.lens"

# Lines past 64 KiB are refused with their line, in every reader.
long=$(head -c 70000 /dev/zero | tr '\0' 1)
{ head -3 "$LENS"; echo "$long"; } >"$T/long.lens"
err_one long_line_lens 'long.lens:4: line longer than 65536 bytes' "$BIN/lens-info" "$T/long.lens"
{ echo "VERS 190000"; echo "NOTE 0 $long"; } >"$T/long.zmx"
err_one long_line_zmx 'long.zmx:2: line longer than 65536 bytes' "$BIN/lens-info" "$T/long.zmx"
{ head -2 lenses/glass.catalog; echo "X$long sellmeier1 1 1 1 1 1 1 0.3 2.5 1.5 60"; } >"$T/long.catalog"
err_one long_line_catalog 'long.catalog:3: line longer than 65536 bytes' \
  "$BIN/lens-info" --glass-catalog "$T/long.catalog" lenses/lensbaby.lens
{ head -4 "$T/s.poly"; echo "meta x $long"; } >"$T/long.poly"
err_one long_line_poly 'long.poly:5: line longer than 65536 bytes' "$BIN/lens-eval" "$T/long.poly" <"$T/s.txt"

# In a stream, a long line or a NUL byte costs its row only (written as nan), named.
{ echo "# columns: x y u v lambda"; echo "0 0 0 0 0.55"; echo "$long"; printf '0 0\0 0 0 0.55\n'; echo "0 0 0 0 0.55"; } >"$T/rows.txt"
out=$(run "$BIN/lens-trace" "$LENS" - <"$T/rows.txt" 2>"$T/err"); rc=$?
rows=$(grep -v '^#' <<<"$out" | awk '{print $1}' | tr '\n' ' ')
if [ $rc -ne 0 ] && [ "$rows" = "0 nan nan 0 " ] && grep -q '<stdin>:3: line longer than' "$T/err" \
   && grep -q '<stdin>:4: NUL byte at column 4' "$T/err"; then ok stream_long_line_and_nul
else fail stream_long_line_and_nul "rc $rc rows '$rows' $(tr '\n' '|' <"$T/err")"; fi

# The design-file importers name a NUL byte with its line too (they read it as a blank,
# so "NAME a<NUL>b" became a name and a NUL inside a keyword an unknown one). A NUL
# character of a UTF-16 file likewise.
printf 'VERS 190000\nNAME a\0b\n' >"$T/nul.zmx"
err_one nul_zmx 'nul.zmx:2: NUL byte at column 7' "$BIN/lens-info" "$T/nul.zmx"
printf 'TITLE x\nS 50\0 5\n' >"$T/nul.seq"
err_one nul_seq 'nul.seq:2: NUL byte at column 5' "$BIN/lens-info" "$T/nul.seq"
python3 -c 'import sys; open(sys.argv[1], "wb").write("VERS 1\nNAME a\0b\n".encode("utf-16"))' "$T/nul16.zmx"
err_one nul_zmx_utf16 'nul16.zmx:2: NUL byte at column 7' "$BIN/lens-info" "$T/nul16.zmx"
{ head -4 tests/data/import/test.agf; printf 'CC a\0b\n'; tail -n +5 tests/data/import/test.agf; } >"$T/nul.agf"
err_one nul_agf 'nul.agf:5: NUL byte at column 5' "$BIN/lens-info" --glass-catalog "$T/nul.agf" lenses/lensbaby.lens

# Nothing an importer reads is cut silently: a glass name too long to hold is an error
# (a cut name could find another glass); all 30 wavelengths are kept, words past the
# 64th of a command and notes past their room are said (the notes end in "...").
printf 'S 50 5 %s\nS -50 40\n' "$(head -c 60 /dev/zero | tr '\0' G)" >"$T/longglass.seq"
err_one seq_long_glass_name "longglass.seq:1: glass name 'GGGGGGGGGGGGGGGGGGGG...' is longer than 47 characters" \
  "$BIN/lens-info" "$T/longglass.seq"
sed 's/^\( *GLAS \)N-BK7/\1NBK7-WITH-A-NAME-FAR-LONGER-THAN-ANY-CATALOG-HOLDS/' tests/data/import/doublet.zmx >"$T/longglass.zmx"
err_one zmx_long_glass_name "longglass.zmx:[0-9]+: glass name 'NBK7-WITH-A-NAME-FAR...' is longer than 47" \
  "$BIN/lens-info" "$T/longglass.zmx"
{ printf 'WL'; for k in $(seq 30); do printf ' %d' $((400 + 10 * k)); done; echo
  for k in $(seq 30); do echo "F${k}$(head -c 40 /dev/zero | tr '\0' x) 1"; done
  printf 'S 50 5 N-BK7\nCIR 10\nS -50 40\nCIR 10\nSTO\n'; } >"$T/many.seq"
notes=$(run "$BIN/lens-info" --format lens "$T/many.seq" 2>/dev/null | grep '^# note:')
grep -q '^# note: wavelengths (um): 0.41 .* 0.7$' <<<"$notes" &&
  grep -q 'skipped: command F1x' <<<"$notes" &&
  [ "$(tail -1 <<<"$notes" | tail -c 4)" = "..." ] && ok import_nothing_cut_silently ||
  fail import_nothing_cut_silently "$notes"

# A UTF-8 byte-order mark before the first line is read as nothing, by every reader.
bom() { printf '\xef\xbb\xbf'; cat "$1"; }
bom "$LENS" >"$T/bom.lens"
a=$(run "$BIN/lens-info" "$LENS" 2>/dev/null | value efl)
b=$(run "$BIN/lens-info" "$T/bom.lens" 2>/dev/null | value efl)
[ -n "$a" ] && [ "$a" = "$b" ] && ok bom_lens || fail bom_lens "efl '$a' vs '$b'"
bom "$T/s.txt" >"$T/bom.txt"
cmp -s <(run "$BIN/lens-trace" "$LENS" - <"$T/s.txt" 2>&1) <(run "$BIN/lens-trace" "$LENS" - <"$T/bom.txt" 2>&1) &&
  ok bom_samples || fail bom_samples "output differs"
bom "$T/s.poly" >"$T/bom.poly"
cmp -s <(run "$BIN/lens-eval" "$T/s.poly" <"$T/s.txt" 2>&1) <(run "$BIN/lens-eval" "$T/bom.poly" <"$T/s.txt" 2>&1) &&
  ok bom_poly || fail bom_poly "output differs"
bom lenses/glass.catalog >"$T/bom.catalog"
a=$(run "$BIN/lens-info" --glass-catalog "$T/bom.catalog" lenses/lensbaby.lens 2>/dev/null | value efl)
b=$(run "$BIN/lens-info" lenses/lensbaby.lens 2>/dev/null | value efl)
[ -n "$a" ] && [ "$a" = "$b" ] && ok bom_catalog || fail bom_catalog "efl '$a' vs '$b'"

# CODE V lines are not cut: a value past column 4095 is read whole.
python3 - "$T/long.seq" <<'PY'
import sys
s = open('tests/data/import/asphere.seq').read().replace('  K -0.6\n', ' ' * 4088 + 'K -0.6123456789\n')
open(sys.argv[1], 'w').write(s)
PY
grep -q 'k=-0.6123456789 ' <(run "$BIN/lens-info" --format lens "$T/long.seq" 2>/dev/null) &&
  ok seq_long_line_whole || fail seq_long_line_whole "k not read whole"

# A text-catalog n_d beyond lens(5)'s bound is refused with its line.
{ head -2 lenses/glass.catalog; echo "HUGE sellmeier1 1 1 1 1 1 1 0.3 2.5 1e154 60"; } >"$T/nd.catalog"
err_one catalog_nd_bound 'nd.catalog:3: glass HUGE: n_d 1e\+154 is above' \
  "$BIN/lens-info" --glass-catalog "$T/nd.catalog" lenses/lensbaby.lens

# ---- -o: in place into FIFOs and devices, through symlinks, whole paths, no leftovers --
O=$T/out; mkdir -p "$O"
mkfifo "$O/fifo"
cat "$O/fifo" >"$T/from-fifo" & reader=$!
run "$BIN/lens-trace" "$LENS" -n 5 --seed 1 -o "$O/fifo" 2>/dev/null; rc=$?
wait $reader
rows=$(grep -vc '^#' "$T/from-fifo")
[ $rc -eq 0 ] && [ -p "$O/fifo" ] && [ "$rows" = 5 ] && ok out_fifo_in_place ||
  fail out_fifo_in_place "rc $rc, fifo kept: $([ -p "$O/fifo" ] && echo yes || echo no), rows $rows"
if [ "$(id -u)" = 0 ] && mknod "$O/null" c 1 3 2>/dev/null; then
  run "$BIN/lens-trace" "$LENS" -n 5 -o "$O/null" 2>/dev/null && [ -c "$O/null" ] &&
    ok out_char_device_kept || fail out_char_device_kept "the device was replaced"
  rm -f "$O/null"
fi
echo old >"$O/real.txt"; ln -s real.txt "$O/link.txt"; ln -s missing.txt "$O/dangling.txt"
run "$BIN/lens-trace" "$LENS" -n 5 -o "$O/link.txt" 2>/dev/null &&
  run "$BIN/lens-trace" "$LENS" -n 5 -o "$O/dangling.txt" 2>/dev/null
[ -L "$O/link.txt" ] && [ -L "$O/dangling.txt" ] && [ "$(grep -vc '^#' "$O/real.txt")" = 5 ] &&
  [ "$(grep -vc '^#' "$O/missing.txt")" = 5 ] && ok out_symlink_followed ||
  fail out_symlink_followed "$(ls -l "$O" | tr '\n' '|')"
rm -f "$O"/*
# A path longer than 1023 characters is written whole (it was cut, exit 0); one the
# system cannot hold is refused.
d=$O; for i in 1 2 3 4 5 6; do d=$d/$(printf 'd%.0s' {1..200}); done; mkdir -p "$d"
run "$BIN/lens-trace" "$LENS" -n 2 -o "$d/rays.txt" 2>/dev/null && [ -s "$d/rays.txt" ] &&
  ok out_long_path_whole || fail out_long_path_whole "not written at its full path"
rm -rf "$O"/d*
err_one out_name_too_long 'File name too long' \
  "$BIN/lens-trace" "$LENS" -n 2 -o "$O/$(printf 'n%.0s' {1..300}).txt"
[ -z "$(ls -A "$O")" ] && ok out_name_too_long_nothing_left || fail out_name_too_long_nothing_left "$(ls "$O")"
# The output is checked before the work: lens-fit with an unwritable -o stops at once,
# without waiting for its input.
start=$(date +%s)
timeout 15 "$BIN/lens-fit" -o "$O/no/such/dir/x.poly" 2>"$T/fit-err" < <(exec sleep 20); rc=$?
err=$(cat "$T/fit-err")
[ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q 'cannot write' <<<"$err" && [ $(( $(date +%s) - start )) -lt 10 ] &&
  ok out_checked_before_work || fail out_checked_before_work "rc $rc: $err"
# Signals beyond INT/TERM/HUP, and a thread library that exits, leave no temporary file.
for sig in XCPU PIPE QUIT; do
  mkdir -p "$O/$sig"
  # A background job of a script starts with SIGQUIT (and SIGINT) ignored, and an ignored
  # signal is left ignored by the command (as nohup expects): restore the default so the
  # signal really arrives, and never wait unbounded for a command that did not die.
  env --default-signal="$sig" "$BIN/lens-trace" "$LENS" -n 1e8 --seed 3 -o "$O/$sig/big.txt" 2>/dev/null & pid=$!
  for _ in $(seq 50); do [ -n "$(ls -A "$O/$sig")" ] && break; sleep 0.1; done
  kill -$sig $pid 2>/dev/null
  for _ in $(seq 100); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
  if kill -0 $pid 2>/dev/null; then
    kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null; fail "out_signal_$sig" "still running 10 s after SIG$sig"
  else
    wait $pid 2>/dev/null
    [ -z "$(ls -A "$O/$sig")" ] && ok "out_signal_$sig" || fail "out_signal_$sig" "left $(ls "$O/$sig")"
  fi
done
if [ -z "$SANITIZE" ]; then
  mkdir -p "$O/threads"
  (ulimit -v 400000; run "$BIN/lens-trace" "$LENS" -n 100000 --threads 1024 -o "$O/threads/x.txt" 2>/dev/null)
  [ -z "$(ls -A "$O/threads")" ] && ok out_thread_failure_nothing_left ||
    fail out_thread_failure_nothing_left "left $(ls "$O/threads")"
fi

# ---- stdout: every command checks its writes and the final flush -----------------------
full() { # full NAME CMD...: stdout to /dev/full must give one "write error" line, exit 1
  local n=$1; shift
  local err
  err=$(run "$@" 2>&1 >/dev/full </dev/null | grep 'write error')
  [ "$(run "$@" >/dev/full 2>/dev/null; echo $?)" != 0 ] &&
    [ "$(grep -c 'write error: No space left on device' <<<"$err")" = 1 ] &&
    [ "$(grep -c '' <<<"$err")" = 1 ] && ok "$n" || fail "$n" "stderr '$err'"
}
if [ -w /dev/full ]; then
  full stdout_full_info "$BIN/lens-info" "$LENS"
  full stdout_full_info_help "$BIN/lens-info" --help
  full stdout_full_spot "$BIN/lens-spot" "$LENS" --rays 50
  full stdout_full_distort "$BIN/lens-distort" "$LENS"
  full stdout_full_trace "$BIN/lens-trace" "$LENS" -n 5
  full stdout_full_fit "$BIN/lens-fit" --terms 3 --degree 2 "$T/s.txt"
  full stdout_full_eval "$BIN/lens-eval" "$T/s.poly" "$T/s.txt"
  full stdout_full_eval_report "$BIN/lens-eval" "$T/s.poly" "$T/s.txt" --report
  full stdout_full_eval_emit "$BIN/lens-eval" "$T/s.poly" --emit c
  full stdout_full_fit_emit "$BIN/lens-fit" --terms 3 --degree 2 "$T/s.txt" --emit c
  # -o onto a full device: the same one line, naming it (these had said "out of memory
  # writing the report", "--name ... is not a C identifier, or writing failed" and
  # "cannot write the system", no reason)
  for spec in "eval_report:lens-eval $T/s.poly $T/s.txt --report" "eval_emit:lens-eval $T/s.poly --emit c" \
              "fit:lens-fit -q --terms 3 --degree 2 $T/s.txt" "fit_emit:lens-fit -q --terms 3 --degree 2 $T/s.txt --emit c"; do
    n=${spec%%:*} cmd=${spec#*:}
    # shellcheck disable=SC2086
    err=$(run "$BIN"/$cmd -o /dev/full 2>&1 >/dev/null); rc=$?
    if [ $rc -ne 0 ] && [ "$(grep -c '' <<<"$err")" = 1 ] &&
       grep -q ': /dev/full: write error: No space left on device$' <<<"$err"
    then ok "file_full_$n"; else fail "file_full_$n" "status $rc: $err"; fi
  done
fi

# ---- scenes: the command line's bounds, no overflow, no inf image, a BOM read ----------
S=$T/scene; mkdir -p "$S"
scene() { printf 'camera %s\nsensor 36 24\nresolution 6 4\nmode grey\nspp 1\nseed 1\n%s\n' \
  "$TOP/lenses/dgauss.50mm.lens" "$1" >"$S/$2.scene"; }
scene 'spp 1e12' spp
err_one scene_spp_bound 'spp.scene:7: .spp. takes a whole number >= 1 \(at most 1073741824' \
  "$BIN/lens-render" "$S/spp.scene" --exact -o "$S/spp.exr"
scene 'plane 0 0 1000  0 0 -1  emit 1e308' emit
err_one scene_emit_bound 'emit.scene:7: .emit. 1e\+308 is above 1e\+30' \
  "$BIN/lens-render" "$S/emit.scene" --exact -o "$S/emit.exr"
# A normal of (0, 0, -1e200) is the normal (0, 0, -1): its squares overflowed to inf,
# the unit normal became 0 and the picture black.
scene 'plane 0 0 1000  0 0 -1  emit 1' n1
scene 'plane 0 0 1000  0 0 -1e200  emit 1' nhuge
run "$BIN/lens-render" "$S/n1.scene" --exact --cache "$S/c" -o "$S/n1.exr" 2>/dev/null &&
  run "$BIN/lens-render" "$S/nhuge.scene" --exact --cache "$S/c" -o "$S/nhuge.exr" 2>/dev/null &&
  cmp -s "$S/n1.exr" "$S/nhuge.exr" && ok scene_normal_no_overflow || fail scene_normal_no_overflow "images differ"
# A checker square of 1e-300 mm: cell indices far past LONG_MAX (was a float-to-long
# overflow, undefined behaviour that clang's UBSan reports): refused, with its line
# (sizes run from 1e-6 to 1e9 mm, lens-scene(5)).
scene 'plane 0 0 1000  0 0 -1  checker 0.2 0.8 1e-300
sphere 0 0 900 300 emit 1' tiny
! "$BIN/lens-render" "$S/tiny.scene" --exact --cache "$S/c" -o "$S/tiny.exr" 2>"$S/tiny.err" &&
  grep -qE 'tiny.scene:[0-9]+: checker square 1e-300 mm is outside' "$S/tiny.err" && [ ! -e "$S/tiny.exr" ] &&
  ! grep -q 'runtime error' "$S/tiny.err" && ok scene_tiny_checker || fail scene_tiny_checker "$(head -2 "$S/tiny.err")"
{ printf '\xef\xbb\xbf'; cat "$S/n1.scene"; } >"$S/bom.scene"
run "$BIN/lens-render" "$S/bom.scene" --exact --cache "$S/c" -o "$S/bom.exr" 2>/dev/null && cmp -s "$S/n1.exr" "$S/bom.exr" &&
  ok bom_scene || fail bom_scene "BOM scene not read as the plain one"

# Subnormal numbers are finite numbers (they were refused as "not finite").
printf 'inf 1 air 10\ninf 1e-310 stop 10\ninf 50 air 10\n' >"$T/sub.lens"
run "$BIN/lens-info" --format lens "$T/sub.lens" 2>/dev/null | grep -q '1e-310' &&
  ok subnormal_accepted || fail subnormal_accepted "1e-310 not read"

# lens-fit names the file and line of a wavelength of 0 (was "sample 2: input lambda is
# not finite", from its 1/lambda^2).
printf '# columns: x y u v lambda out_x out_y out_u out_v out_eta\n0 0 0 0 0.5 0 0 0 0 1\n1 0 0 0 0 0 0 0 0 1\n' >"$T/lam0.txt"
err_one fit_lambda_zero_named 'lam0.txt:3: input lambda is 0: a wavelength must be > 0 um' "$BIN/lens-fit" "$T/lam0.txt"

# A .poly's parts cost memory for the terms they hold, not for the inputs x outputs
# tables of each declared part (64 inputs, 64 outputs and 64 parts, 1.2 KB, took 9 MB
# more than one part; every part now shares one set of empty tables until its first
# term). Peak RSS of lens-eval reading it, against the same header with one part.
poly_header() {
  echo 'lens-poly 1'; echo 'lens t'
  printf 'inputs x y'; for k in $(seq 62); do printf ' i%d' "$k"; done; echo
  printf 'outputs'; for k in $(seq 64); do printf ' o%d' "$k"; done; echo
}
{ poly_header; echo 'part 0 inf'; echo end; } >"$T/one.poly"
{ poly_header; for k in $(seq 0 62); do echo "part $k $((k + 1))"; for o in $(seq 64); do echo "output o$o 0"; done; done
  echo 'part 63 inf'; echo end; } >"$T/parts.poly"
poly_rss() { # peak RSS (kB) of lens-eval reading $1 (it then stops at the empty stream)
  ASAN_OPTIONS="${ASAN_OPTIONS:-}:quarantine_size_mb=0:thread_local_quarantine_size_kb=0" \
    /usr/bin/time -f %M -o "$T/rss" "$BIN/lens-eval" "$1" </dev/null >/dev/null 2>&1
  tail -1 "$T/rss"
}
if [ -x /usr/bin/time ]; then
  a=$(poly_rss "$T/one.poly") b=$(poly_rss "$T/parts.poly")
  [ "$b" -le $((a + 2048)) ] && ok "poly_parts_memory (64 declared parts: $b kB, one part: $a kB)" ||
    fail poly_parts_memory "64 declared parts: $b kB, one part: $a kB"
else ok "poly_parts_memory (skipped: /usr/bin/time not installed)"; fi
