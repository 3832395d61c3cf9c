#!/usr/bin/env bash
# The examples of the documentation, extracted and run as printed.
#
#   tools/doc-examples.sh --list FILE...          print each example block, "#@ FILE:LINE" first
#   tools/doc-examples.sh --run DIR FILE...       run each file's blocks in order, in DIR/<file>/
#
# What counts as an example:
#  - README.md (any .md): every line starting with "$ " (the prompt is removed; a line
#    ending in a backslash continues on the next line). All lines of one file run in one
#    shell, in order, like a user typing them: `export` and `cd` carry over.
#  - man pages (*.[1-8]): every .nf/.fi (or .EX/.EE) block of a section whose name
#    starts with EXAMPLE, roff requests (.RS, .IP, ...) left out and roff escapes turned
#    into what man prints (\- -, \e \, \(aq ', ...). Every block is shell input: a file's
#    contents are shown by the command that writes it (cat > FILE <<'EOF' ... EOF).
# --run runs each file's blocks in one bash (pipefail; standard input /dev/null) in its
# own directory DIR/<file name>, which the caller prepares (README: a plain clone; man
# pages: an empty directory). A block fails when one of its commands exits non-zero (a
# writer killed by SIGPIPE because the reader stopped early, `| head`, is not a failure),
# or when its last command is a filter (awk, grep, sed) and it prints nothing.
# Output: "ok docs FILE (N examples, S s)" or "FAIL docs FILE:LINE: <the command>" and the tail
# of its stderr; exit 1 if any block failed. The caller sets PATH, XDG_CACHE_HOME, ...
set -u

extract() { # FILE
  case $1 in
    *.md)
      awk -v f="$1" '
        cont { print; cont = /\\$/; next }
        /^\$ / { printf "#@ %s:%d\n", f, NR; sub(/^\$ /, ""); print; cont = /\\$/ }' "$1" ;;
    *)
      awk -v f="$1" '
        function unroff(s) {
          gsub(/\\\\/, "\001", s)            # an escaped backslash, kept aside
          gsub(/\\-/, "-", s); gsub(/\\e/, "\001", s)
          gsub(/\\\(aq/, "\047", s); gsub(/\\\(dq/, "\"", s); gsub(/\\\(ti/, "~", s)
          gsub(/\\\(ha/, "^", s); gsub(/\\\(ga/, "`", s); gsub(/\\\(em/, "--", s)
          gsub(/\\&/, "", s); gsub(/\\f[BIRP]/, "", s); gsub(/\\f\(CW/, "", s); gsub(/\\ /, " ", s)
          gsub(/\001/, "\\", s)
          return s
        }
        /^\.SH/ { ex = ($0 ~ /^\.SH +"?EXAMPLE/); inblock = 0; next }
        ex && /^\.(nf|EX)/ { inblock = 1; printf "#@ %s:%d\n", f, NR + 1; next }
        ex && /^\.(fi|EE)/ { inblock = 0; next }
        ex && inblock && /^\.[A-Za-z]/ { next }
        ex && inblock { print unroff($0) }' "$1" ;;
  esac
}

# Writes the bash script that runs FILE's blocks (each block's stdout and stderr to
# files in LOGDIR). A failure is recorded once per block, with the line of the failing
# command in FILE (the script knows where each block's first line is).
script_for() { # FILE LOGDIR
  local file=$1 logs=$2 n=0 loc="" body="" at=3
  echo 'set -o pipefail'
  echo "fails=$logs/fails; : > \"\$fails\""
  # A pipeline element that met a reader which stopped early is no failure: killed by
  # SIGPIPE (141), or, not last, exited with EPIPE (32, python3's way).
  echo 'trap '\''ps=("${PIPESTATUS[@]}"); rc=0; n=${#ps[@]}; for ((i = 0; i < n; i++)); do s=${ps[i]}; if [ "$s" != 0 ] && [ "$s" != 141 ] && { [ "$s" != 32 ] || [ $i -eq $((n - 1)) ]; }; then rc=$s; fi; done; if [ $rc -ne 0 ] && [ "${reported:-}" != "$K" ]; then echo "$K $F:$((L0 + LINENO - B0)) $rc $((LINENO - B0 + 1))" >> "$fails"; reported=$K; fi'\'' ERR'
  flush() {
    [ -n "$loc" ] || return 0
    n=$((n + 1))
    # the block ends in ':' so that only its commands, never the block, trip the trap
    printf 'K=%d F=%q L0=%d B0=%d\n{\n%s\n:\n} < /dev/null > %q 2> %q\n' "$n" "${loc%:*}" "${loc##*:}" \
      $((at + 3)) "$body" "$logs/$n.out" "$logs/$n.err"
    printf 'echo "$SECONDS" > %q\n' "$logs/$n.end"
    at=$((at + 5 + $(printf '%s\n' "$body" | wc -l)))
    printf '%s\n' "$body" > "$logs/$n.cmd"
    printf '%s\n' "$loc" > "$logs/$n.loc"
  }
  while IFS= read -r line; do
    if [[ $line == "#@ "* ]]; then flush; loc=${line#\#@ }; body=""
    else body+=${body:+$'\n'}$line; fi
  done < <(extract "$file")
  flush
}

case ${1:-} in
  --list)
    shift
    for f in "$@"; do extract "$f"; done ;;
  --run)
    dir=$2; shift 2
    status=0
    for f in "$@"; do
      name=$(basename "$f")
      logs=$dir/.logs/$name
      rm -rf "$logs"; mkdir -p "$logs" "$dir/$name"
      script_for "$f" "$logs" > "$logs/script.sh"
      count=$(ls "$logs" | grep -c '\.cmd$')
      ( cd "$dir/$name" && timeout 900 bash "$logs/script.sh" ); rc=$?
      [ $rc -ne 124 ] || echo "0 $f:timeout 124 1" >> "$logs/fails"
      # a block that ends in a filter (awk, grep, sed) and prints nothing: the filter
      # matched nothing, so the example shows nothing of what it promises
      for ((k = 1; k <= count; k++)); do
        last=$(grep -v '^[[:space:]]*$' "$logs/$k.cmd" | tail -n 1)
        if [ -f "$logs/$k.out" ] && [ ! -s "$logs/$k.out" ] &&
           grep -qE "\|[[:space:]]*(awk|grep|sed)[[:space:]]" <<<"$last" &&
           ! grep -q "^$k " "$logs/fails"; then
          n_lines=$(grep -c '' "$logs/$k.cmd") loc=$(cat "$logs/$k.loc")
          echo "$k ${loc%:*}:$((${loc##*:} + n_lines - 1)) nothing $n_lines" >> "$logs/fails"
        fi
      done
      if [ -s "$logs/fails" ]; then
        status=1
        while read -r k loc rc idx; do
          what="exit $rc"
          [ "$rc" != nothing ] || what="printed nothing"
          echo "FAIL docs $loc: $what: $(sed -n "${idx}p" "$logs/$k.cmd" 2>/dev/null | head -c 300)"
          tail -n 4 "$logs/$k.err" 2>/dev/null | sed 's/^/    /'
        done < "$logs/fails"
      elif [ "$count" -gt 0 ]; then
        echo "ok docs $f ($count examples, $(cat "$logs/$count.end" 2>/dev/null) s)"
      fi
    done
    exit $status ;;
  *)
    sed -n '2,/^set -u/p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2 ;;
esac
