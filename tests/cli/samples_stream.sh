#!/usr/bin/env bash
# The sample reader on streams: files joined by cat whose '# columns:' lines order the
# columns differently, and a line that never ends.
source "$(dirname "$0")/lib.sh"
LENS=lenses/simple.lens

# Two files, the same columns in other orders, with an id carried through: the joined
# stream gives each file's own rows, in the first file's column order.
{ echo "# columns: x y u v lambda id"
  echo "0.5 -0.25 0.01 0.02 0.55 a1"; echo "1 0.5 -0.02 0 0.6 a2"; } >"$T/a.txt"
{ echo "# lens: other"; echo "# columns: id lambda v u y x"
  echo "b1 0.5 0.03 -0.01 0.75 -1"; echo "b2 0.65 0 0.02 -0.5 0.25"; } >"$T/b.txt"
# b's rows written in a's order, by hand: the reference for the joined stream
{ echo "# columns: x y u v lambda id"
  echo "-1 0.75 -0.01 0.03 0.5 b1"; echo "0.25 -0.5 0.02 0 0.65 b2"; } >"$T/b_as_a.txt"
run "$BIN/lens-trace" "$LENS" - <"$T/a.txt" >"$T/ta.txt" &&
  run "$BIN/lens-trace" "$LENS" - <"$T/b_as_a.txt" >"$T/tb.txt" &&
  cat "$T/a.txt" "$T/b.txt" | run "$BIN/lens-trace" "$LENS" - >"$T/tab.txt"
if [ $? -eq 0 ] && diff <(grep -hv '^#' "$T/ta.txt" "$T/tb.txt") <(grep -v '^#' "$T/tab.txt") >/dev/null &&
   [ "$(grep -c '^# columns:' "$T/tab.txt")" = 1 ]; then ok joined_files_trace
else fail joined_files_trace "$(grep -v '^#' "$T/tab.txt" | tr '\n' '|')"; fi

# lens-eval: out_x = x, so the second file's x must come out where the first's did.
{ echo "# columns: x y id"; echo "1 2 a"; } >"$T/e1.txt"
{ echo "# columns: id y x"; echo "b 5 3"; echo "c 7 -4"; } >"$T/e2.txt"
out=$(cat "$T/e1.txt" "$T/e2.txt" | run "$BIN/lens-eval" tests/data/eval_tiny.poly 2>&1)
rows=$(grep -v '^#' <<<"$out" | awk '{ print $1, $2, $3, $NF }' | tr '\n' '|')
if [ "$rows" = "1 2 1 a|3 5 3 b|-4 7 -4 c|" ]; then ok joined_files_eval
else fail joined_files_eval "$rows"; fi

# Other columns in the second file are refused where they are named, nothing read after.
{ echo "# columns: x y id extra"; echo "3 5 b 0"; } >"$T/e3.txt"
err=$(cat "$T/e1.txt" "$T/e3.txt" | run "$BIN/lens-eval" tests/data/eval_tiny.poly 2>&1 >"$T/out"); rc=$?
if [ $rc -ne 0 ] && grep -q "<stdin>:3: a second '# columns:' line adds column 'extra'" <<<"$err" &&
   ! grep -q '^3 ' "$T/out"; then ok joined_other_columns_refused
else fail joined_other_columns_refused "rc $rc: $err"; fi
{ echo "# columns: x y u v id"; echo "3 b 0 0 c"; } >"$T/e4.txt"
expect_error joined_fewer_columns_refused "<stdin>:4: a second '# columns:' line lacks column 'lambda'" \
  sh -c "cat '$T/a.txt' '$T/e4.txt' | '$BIN/lens-trace' '$LENS' -"
expect_error joined_fit_refused "a second '# columns:' line lacks column" \
  sh -c "{ '$BIN/lens-trace' '$LENS' -n 300 --seed 1; echo '# columns: x y'; } | '$BIN/lens-fit' - -o '$T/s.poly'"

# A line that never ends, on a stream: refused while the stream is still open (the
# writer holds it open until the message has come, for up to a minute), not after.
never_ends() { # NAME HEADER CMD...: CMD reads the stream on stdin
  local n=$1 header=$2; shift 2
  rm -f "$T/seen" "$T/err"; mkfifo "$T/fifo.$n"
  "$@" <"$T/fifo.$n" >/dev/null 2>"$T/err" &
  local pid=$!
  {
    printf '%s\n' "$header"
    head -c 70000 /dev/zero | tr '\0' 1
    for _ in $(seq 600); do
      if grep -q 'line longer than 65536 bytes' "$T/err" 2>/dev/null; then : >"$T/seen"; break; fi
      sleep 0.1
    done
  } >"$T/fifo.$n"
  wait $pid
  if [ -e "$T/seen" ] && grep -q '<stdin>:2: line longer than 65536 bytes' "$T/err"; then ok "$n"
  else fail "$n" "no message while the line went on: $(head -c 300 "$T/err")"; fi
}
never_ends never_ending_line_trace '# columns: x y u v lambda' "$BIN/lens-trace" "$LENS" -
never_ends never_ending_line_eval '# columns: x y' "$BIN/lens-eval" tests/data/eval_tiny.poly
never_ends never_ending_line_fit "$("$BIN/lens-trace" "$LENS" -n 1 | grep '^# columns:')" \
  "$BIN/lens-fit" - -o "$T/never.poly"
