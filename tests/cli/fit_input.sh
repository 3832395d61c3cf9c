#!/usr/bin/env bash
# lens-fit's data errors: every one names the file and a line and says what is
# wrong in the file's own columns and units, never in the fitter's scaled or framed
# variables ("sample 3: input x is not finite" for 1e308, "constant (3.3057...)" for a
# wavelength of 0.55 um, "input v is constant (0)" for meridional rays); no file is left.
source "$(dirname "$0")/lib.sh"
F=$BIN/lens-fit

# 300 rays of a made-up smooth lens (no tracing: the point is the messages). Columns
# x y u v lambda out_x out_y out_u out_v out_eta; every seventh ray blocked.
awk -v CONVFMT=%.17g -v OFMT=%.17g 'BEGIN {
  print "# columns: x y u v lambda out_x out_y out_u out_v out_eta"; s = 7
  for (i = 0; i < 300; i++) {
    s = (s * 1103515245 + 12345) % 2147483648; x = 20 * s / 2147483648 - 10
    s = (s * 1103515245 + 12345) % 2147483648; y = 20 * s / 2147483648 - 10
    s = (s * 1103515245 + 12345) % 2147483648; u = 0.4 * s / 2147483648 - 0.2
    s = (s * 1103515245 + 12345) % 2147483648; v = 0.4 * s / 2147483648 - 0.2
    s = (s * 1103515245 + 12345) % 2147483648; l = 0.4 + 0.3 * s / 2147483648
    if (i % 7 == 6) { print x, y, u, v, l, "nan nan nan nan 0"; continue }
    print x, y, u, v, l, x + 40 * u + 0.01 * x * l, y + 40 * v, u - 0.02 * x, v - 0.02 * y, 0.9
  } }' >"$T/s.txt"
# row N (1-based among data rows) is file line N + 1

# fit_err NAME PATTERN FILE [FLAGS]: exit 1, one stderr line matching PATTERN, no -o file.
fit_err() {
  local n=$1 pat=$2 f=$3; shift 3
  local err rc
  err=$(run "$F" -q --terms 6 --degree 3 "$@" "$f" -o "$T/out.poly" 2>&1 >/dev/null); rc=$?
  if [ $rc -ne 1 ]; then fail "$n" "exit $rc: $err"
  elif [ -e "$T/out.poly" ]; then fail "$n" "output file left behind"
  elif [ "$(grep -c '' <<<"$err")" -ne 1 ] || ! grep -qE -- "$pat" <<<"$err"; then
    fail "$n" "stderr '$err' does not match '$pat'"
  else ok "$n"; fi
  rm -f "$T/out.poly"
}
# set_field ROW COL VALUE < samples: the file with one value replaced
set_field() { awk -v r="$1" -v c="$2" -v v="$3" '!/^#/ && ++n == r { $c = v } 1'; }

if run "$F" -q --terms 6 --degree 3 "$T/s.txt" -o "$T/ok.poly" 2>/dev/null && [ -s "$T/ok.poly" ]; then
  ok fit_input_valid; else fail fit_input_valid "the clean file did not fit"; fi

# 1e308 is finite: out of range, with its line (was "sample 3: input x is not finite",
# from the frame's x^2 + y^2); outputs likewise (were fitted with one term, exit 0).
set_field 3 1 1e308 <"$T/s.txt" >"$T/big.txt"
fit_err fit_input_huge 'big.txt:4: input x is 1e\+308: out of range \(values must lie within \+-1e100\)$' "$T/big.txt"
set_field 3 6 -1e300 <"$T/s.txt" >"$T/bigout.txt"
fit_err fit_output_huge 'bigout.txt:4: output out_x is -1e\+300: out of range' "$T/bigout.txt"
set_field 3 6 inf <"$T/s.txt" >"$T/infout.txt"
fit_err fit_output_inf 'infout.txt:4: output out_x is inf: outputs must be finite or nan' "$T/infout.txt"
set_field 5 5 1e-200 <"$T/s.txt" >"$T/tiny.txt"
fit_err fit_input_tiny_lambda 'tiny.txt:6: input lambda is 1e-200: out of range \(a wavelength' "$T/tiny.txt"
# 1e100 itself is taken (a row far outside the rest, but a number the fit can hold)
set_field 3 1 1e100 <"$T/s.txt" >"$T/edge.txt"
run "$F" -q --terms 6 --degree 3 "$T/edge.txt" -o "$T/edge.poly" 2>/dev/null && ok fit_input_edge_taken ||
  fail fit_input_edge_taken "1e100 refused"

# A single wavelength as an input: its value in um, not 1/lambda^2 (was 3.3057...).
awk '!/^#/ { $5 = 0.55 } 1' "$T/s.txt" >"$T/mono.txt"
fit_err fit_input_constant_lambda 'mono.txt:2: input lambda is 0.55 um on all 258 usable samples \(lines 2 to 301\): leave it out of --inputs' "$T/mono.txt"
# ... and fitted without it
run "$F" -q --terms 6 --degree 3 --inputs x,y,u,v "$T/mono.txt" -o "$T/mono.poly" 2>/dev/null &&
  grep -q '^meta lambda 0.55' "$T/mono.poly" && ok fit_input_mono_without_lambda ||
  fail fit_input_mono_without_lambda "not fitted"
# a column varying by round-off only
awk -v OFMT=%.17g '!/^#/ { $5 = 0.55 + (NR % 2) * 1e-16 } 1' "$T/s.txt" >"$T/round.txt"
fit_err fit_input_roundoff 'round.txt:2: input lambda (is 0.55|varies only from) ' "$T/round.txt"

# Meridional rays only (direction along the sensor point): the frame's skew direction is
# 0 on every ray (was "input v is constant (0)", of a v column that is not constant).
awk -v CONVFMT=%.17g -v OFMT=%.17g '!/^#/ { $2 = 0.5 * $1; $4 = 0.5 * $3 } 1' "$T/s.txt" >"$T/merid.txt"
fit_err fit_input_meridional "merid.txt:2: the skew direction v' = \(x v - y u\) / r of the meridional frame is 0 on all 258 usable samples .*meridional ray.*--frame none" "$T/merid.txt"
run "$F" -q --terms 6 --degree 3 --frame none "$T/merid.txt" -o "$T/merid.poly" 2>/dev/null &&
  ok fit_input_meridional_frame_none || fail fit_input_meridional_frame_none "not fitted"
# every ray at one sensor radius
awk -v CONVFMT=%.17g -v OFMT=%.17g '!/^#/ { r = sqrt($1 * $1 + $2 * $2); $1 = 5 * $1 / r; $2 = 5 * $2 / r } 1' \
  "$T/s.txt" >"$T/ring.txt"
fit_err fit_input_one_radius 'ring.txt:2: the sensor radius r = sqrt\(x\^2 \+ y\^2\) of the meridional frame is 5 mm on all' "$T/ring.txt"

# Every ray blocked: the file, no line (there is none to name).
awk '!/^#/ { $6 = "nan"; $10 = 0 } 1' "$T/s.txt" >"$T/blocked.txt"
fit_err fit_input_all_blocked 'blocked.txt: none of the 300 samples is usable: every ray is blocked' "$T/blocked.txt"

# Standard input is named <stdin>.
err=$(run "$F" -q --terms 6 --degree 3 <"$T/big.txt" 2>&1 >/dev/null)
grep -q '^lens-fit: <stdin>:4: input x is 1e+308' <<<"$err" && ok fit_input_stdin_named ||
  fail fit_input_stdin_named "$err"

# The samples' "# fnumber:" line (lens-trace --fnumber) goes into the system, and
# lens-spot stops the system's lens down to it (the lens alone is f/1.48).
run "$BIN/lens-trace" lenses/simple.lens -n 300 --seed 1 --fnumber 8 -o "$T/f8.txt" 2>/dev/null
run "$F" -q --terms 6 --degree 3 "$T/f8.txt" -o "$T/f8.poly" 2>/dev/null
grep -qx 'meta fnumber 8' "$T/f8.poly" && ok fit_records_fnumber ||
  fail fit_records_fnumber "$(grep '^meta fnumber' "$T/f8.poly")"
t1=$(run "$BIN/lens-spot" "$T/f8.poly" 2>/dev/null | grep -o ': f/[0-9.]*,' | head -1)
t2=$(run "$BIN/lens-spot" "$T/f8.poly" --fnumber 4 2>/dev/null | grep -o ': f/[0-9.]*,' | head -1)
[ "$t1" = ": f/8," ] && [ "$t2" = ": f/4," ] && ok spot_system_fnumber ||
  fail spot_system_fnumber "'$t1' '$t2'"
sed 's/^# fnumber: .*/# fnumber: eight/' "$T/f8.txt" >"$T/fbad.txt"
fit_err fit_bad_fnumber "fbad.txt: '# fnumber: eight': expected a positive f-number" "$T/fbad.txt"
