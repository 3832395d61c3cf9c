# shellcheck shell=bash disable=SC2034  # sets SENSOR_FLAGS, NEEDS, TOP, TOP_FROM for the caller
# Functions of tools/realworld.sh that tests/cli/realworld.sh uses too (sourced; BIN and
# D_LINE set by the caller).
# The one place that supplies what a command cannot yet find by itself in an imported
# file: a sensor size for lens-trace (and the top field for lens-spot/lens-distort).
# Sets SENSOR_FLAGS (flags for lens-trace), NEEDS (what the row is marked with, or -),
# TOP (the top field, deg) and TOP_FROM (where it came from).
# Rules: a lens with a sensor in its header, or fields that imply one (lens-info prints
# it), needs nothing; its top field is the largest of the commands' default fields. Otherwise the file's largest field (angle, or real image
# height) gives the image height h of its chief ray, and the sensor is 3:2 with
# half-diagonal 1.05 h (a margin so that the top field's spot lies inside the data
# the system is fitted on); a file that states only the axis gets a 1-degree half
# field; a file that states no field at all gets a sensor inside its image circle.
sensor_for() { # FILE INFO_FILE LENS_FILE(lens-info --format lens)
  local f=$1 info=$2 lens=$3 fld typ h deg circ
  SENSOR_FLAGS="" NEEDS=- TOP="" TOP_FROM=""
  if grep -q '^sensor ' "$info"; then
    # a sensor in the header, or the one the file's fields imply: the commands need no
    # flag, and the top field is the largest of their default fields (the file's own)
    TOP=$("$BIN"/lens-spot "$f" --rays 4 2>/dev/null |
      awk '!/^#/ && $1 == "lens" { n++; if ($2 + 0 > m) m = $2 + 0 } END { if (n) print m }')
    TOP_FROM="the commands' default top field"
    # the axis alone in the file: the 1 degree its sensor is made for (lens-trace(1))
    [ "$TOP" = 0 ] && TOP=1 TOP_FROM="axis only in the file: the 1 deg its sensor is made for"
    [ -n "$TOP" ] && return
    TOP=$(awk '$1 == "field_of_view_deg" { print $2 / 2 }' "$info")
    TOP_FROM="sensor corner"
    return
  fi
  NEEDS="--sensor"
  fld=$(sed -n 's/^# note: fields \(.*\): \(.*\)$/\1|\2/p' "$lens" | head -1)
  typ=${fld%%|*}
  h=""
  case "$typ" in
    "angle (deg)")
      deg=$(echo "${fld#*|}" | tr ' ' '\n' | awk 'NF { v = $1 < 0 ? -$1 : $1; if (v > m) m = v } END { print m + 0 }')
      if awk -v d="$deg" 'BEGIN { exit !(d == 0) }'; then
        deg=1 TOP_FROM="axis only in the file: 1 deg"
      else
        TOP_FROM="file's top field"
      fi
      TOP=$deg
      h=$("$BIN"/lens-distort "$f" --fields "$deg" --illum-rays 0 2>/dev/null |
        awk '$1 == "lens" && $2 != 0 { print $3 }' | tail -1) ;;
    "real image height"|"image height"|"paraxial image height")
      h=$(echo "${fld#*|}" | tr ' ' '\n' | awk 'NF { v = $1 < 0 ? -$1 : $1; if (v > m) m = v } END { print m + 0 }')
      TOP_FROM="file's top image height $h mm" ;;
  esac
  case "$h" in nan|-nan|inf|-inf|0) h="" ;; esac
  if [ -z "$h" ]; then
    circ=$("$BIN"/lens-info "$f" --sensor 10000x10000 2>/dev/null | awk '$1 == "image_circle_radius" { print $2 }')
    [ -n "$circ" ] || return
    h=$(awk -v c="$circ" 'BEGIN { print 0.9 * c / 1.05 }')
    if [ -n "$TOP_FROM" ]; then
      TOP_FROM="$TOP_FROM (no chief ray there): 0.9 of the image circle"; TOP=""
    else
      TOP_FROM="no field in the file: 0.9 of the image circle"
    fi
  fi
  SENSOR_FLAGS="--sensor $(awk -v h="$h" 'BEGIN { d = 1.05 * h; printf "%.6gx%.6g", 2 * d * 3 / sqrt(13), 2 * d * 2 / sqrt(13) }')"
  if [ -z "$TOP" ]; then
    # the top field is where the chief ray reaches h: half the field of view of a
    # sensor whose half-diagonal is h
    TOP=$("$BIN"/lens-info "$f" --sensor "$(awk -v h="$h" 'BEGIN { printf "%.6gx%.6g", 2 * h * 3 / sqrt(13), 2 * h * 2 / sqrt(13) }')" 2>/dev/null |
      awk '$1 == "field_of_view_deg" { print $2 / 2 }')
  fi
}

# efl from one exact ray: x = h, direction along the axis, d line. out_u, out_v are the
# direction's components in the tangent frame of the front surface at the hit
# (lens-samples(5)), so the direction in the lens frame needs that surface's normal:
# from the first surface of `lens-info --format lens` (radius, conic, a4..a12).
efl_check() { # FILE LENS_FILE -> efl or "nan"
  local f=$1 lens=$2 sd h
  sd=$(awk '!/^#/ && NF >= 4 { print $4; exit }' "$lens")
  h=$(awk -v s="$sd" 'BEGIN { print (s > 0 ? s : 1) * 1e-3 }')
  printf '# columns: x y u v lambda\n%s 0 0 0 %s\n' "$h" "$D_LINE" |
    "$BIN"/lens-trace "$f" - 2>/dev/null |
    awk -v h="$h" -v lens="$lens" '
      BEGIN {
        while ((getline line < lens) > 0) {
          if (line ~ /^#/ || (nw = split(line, w)) < 4) continue
          r = w[1]; c = (r == "inf" || r == "-inf") ? 0 : 1 / r; k = 0
          for (i = 5; i <= nw; i++) if (split(w[i], kv, "=") == 2) a[kv[1]] = kv[2] + 0
          if ("k" in a) k = a["k"]
          break
        }
      }
      /^# columns:/ { for (i = 3; i <= NF; i++) col[$i] = i - 2; next }
      /^#/ { next }
      {
        x = $(col["out_x"]); y = $(col["out_y"]); u = $(col["out_u"]); v = $(col["out_v"])
        if ($(col["out_eta"]) == 0 || x == "nan") { print "nan"; exit }
        # sag slope of the front surface at radius rho, then the normal towards object space
        rho = sqrt(x * x + y * y)
        s = c * rho / sqrt(1 - (1 + k) * c * c * rho * rho)
        for (p = 4; p <= 12; p += 2) if (("a" p) in a) s += p * a["a" p] * rho ^ (p - 1)
        nrm = sqrt(1 + s * s); sn = s / nrm
        nx = (rho > 0 ? sn * x / rho : 0); ny = (rho > 0 ? sn * y / rho : 0); nz = -1 / nrm
        kk = 1 / (1 - nz)
        exx = 1 - kk * nx * nx; exy = -kk * nx * ny; exz = nx
        eyx = -kk * nx * ny; eyy = 1 - kk * ny * ny; eyz = ny
        wz = sqrt(1 - u * u - v * v)
        dx = u * exx + v * eyx + wz * nx
        dy = u * exy + v * eyy + wz * ny
        st = sqrt(dx * dx + dy * dy)
        if (st == 0) print "inf"; else printf "%.10g\n", h / st
        exit
      }'
}

# does the file hold a mirror anywhere (the importer names only its first refusal)?
has_mirror() {
  local bom
  bom=$(head -c2 "$1" | od -An -tx1 | tr -d ' ')
  if [ "$bom" = fffe ] || [ "$bom" = feff ]; then iconv -f UTF-16 -t UTF-8 "$1"; else cat "$1"; fi |
    grep -qiE '^[[:space:]]*GLAS[[:space:]]+MIRROR|(^|[[:space:];])REFL([[:space:];]|$)'
}
