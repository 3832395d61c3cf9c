#!/usr/bin/env bash
# `make deps`: makes sure what sparselens needs is there.
#
# Every need is probed directly (a compiler on PATH, a header that compiles and a
# library that links with the flags the Makefile found through pkg-config), never by
# asking a package manager, so any system where the libraries are present builds,
# Debian or not. What is missing is installed only where that is possible: apt-get on
# PATH and root, or sudo without a password; always with --no-install-recommends (the
# full OpenCV dev package pulls in 800 MB). Otherwise the script names what is missing,
# with the Debian packages that provide it, and goes on.
#
# Required (the build and the unit tests): C and C++ compilers, OpenMP, OpenCV 4 (core,
# imgproc, imgcodecs, calib3d), OpenEXR Core, PROJ (GeographicLib's geodesic C API),
# LAPACKE, cmocka, double-conversion, fast_float. Missing required parts make the exit status 1.
# Optional (each test that needs one skips without it): pkg-config (the Makefile falls
# back to asking the compiler), python3 and gnuplot (make reports), GNU parallel (the
# scale-out test), valgrind, clang with libFuzzer (make fuzz, the short fuzz test).
#
# Environment: CC, CXX, MAKE as for make; DEPS_INSTALL=no never installs, only reports.
set -u
cd "$(dirname "$0")/.."
CC=${CC:-cc} CXX=${CXX:-c++}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

makevar() { env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL "${MAKE:-make}" -s --no-print-directory "print-$1" 2>/dev/null; }

# compiles LANG SOURCE FLAGS...: the source compiles and links.
compiles() {
  local lang=$1 src=$2; shift 2
  local cc=$CC; [ "$lang" = c++ ] && cc=$CXX
  printf '%b' "$src" >"$tmp/probe.$lang"
  # shellcheck disable=SC2068
  "$cc" -x "$lang" "$tmp/probe.$lang" -o "$tmp/probe" $@ >/dev/null 2>&1
}

# The probes, one per need: NAME|required/optional|Debian packages|what it is for.
needs() {
cat <<'EOF'
cc|required|build-essential|the C compiler (CC)
c++|required|build-essential|the C++ compiler (CXX), for the OpenCV shim
openmp|required|build-essential|OpenMP threads
opencv|required|libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-calib3d-dev|OpenCV 4: the distortion check (camera-model fits)
cairo|required|libcairo2-dev|cairo: pictures with real fonts (µm), PNG, SVG and PDF
openexr|required|libopenexr-dev|OpenEXR Core: HDR images and renders
proj|required|libproj-dev|PROJ's geodesic API (GeographicLib)
lapacke|required|liblapacke-dev|LAPACKE: QR in lens-fit
cmocka|required|libcmocka-dev|cmocka: the unit tests
double-conversion|required|libdouble-conversion-dev|double-conversion: the shortest digits of the numbers samples write
fast_float|required|libfast-float-dev|fast_float: exact parsing of the numbers samples read (header-only)
pkg-config|optional|pkg-config|library flags (the Makefile otherwise asks the compiler)
python3|optional|python3|make reports
gnuplot|optional|gnuplot-nox|make reports
parallel|optional|parallel|the scale-out test (tests/cli/scaleout.sh)
valgrind|optional|valgrind|tests/cli/valgrind.sh
libfuzzer|optional|clang libclang-rt-dev|make fuzz and the short fuzz test
EOF
}

have() {
  case $1 in
    cc) command -v "$CC" >/dev/null ;;
    c++) command -v "$CXX" >/dev/null ;;
    openmp) compiles c '#include <omp.h>\nint main(void) { return omp_get_max_threads() < 1; }\n' -fopenmp ;;
    opencv) compiles c++ '#include <opencv2/core.hpp>\n#include <opencv2/imgproc.hpp>\n#include <opencv2/imgcodecs.hpp>\n#include <opencv2/calib3d.hpp>\nint main() { cv::Mat m = cv::Mat::eye(2, 2, CV_64F); return m.rows != 2; }\n' \
              $(makevar OPENCV_CFLAGS) $(makevar OPENCV_LIBS) ;;
    cairo) compiles c '#include <cairo.h>\nint main(void) { cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1); cairo_surface_destroy(s); return 0; }\n' \
             $(makevar CAIRO_CFLAGS) $(makevar CAIRO_LIBS) ;;
    openexr) compiles c '#include <openexr.h>\nint main(void) { int a, b, c; exr_get_library_version(&a, &b, &c, 0); return 0; }\n' \
               $(makevar EXR_CFLAGS) $(makevar EXR_LIBS) ;;
    proj) compiles c '#include <geodesic.h>\nint main(void) { struct geod_geodesic g; geod_init(&g, 1, 0); return 0; }\n' \
            $(makevar PROJ_CFLAGS) $(makevar PROJ_LIBS) -lm ;;
    lapacke) compiles c '#include <lapacke.h>\nint main(void) { double a = 2, t; return LAPACKE_dgeqrf(LAPACK_COL_MAJOR, 1, 1, &a, 1, &t); }\n' \
               $(makevar LAPACK_CFLAGS) $(makevar LAPACK_LIBS) -lm ;;
    cmocka) compiles c '#include <stdarg.h>\n#include <stddef.h>\n#include <setjmp.h>\n#include <cmocka.h>\nint main(void) { return 0; }\n' \
              $(makevar CMOCKA_CFLAGS) $(makevar CMOCKA_LIBS) ;;
    double-conversion) compiles c++ '#include <double-conversion/double-to-string.h>\nint main() { char d[18]; bool s; int n, p; double_conversion::DoubleToStringConverter::DoubleToAscii(0.5, double_conversion::DoubleToStringConverter::SHORTEST, 0, d, 18, &s, &n, &p); return n != 1; }\n' \
                         $(makevar DCONV_LIBS) ;;
    fast_float) compiles c++ '#include <fast_float/fast_float.h>\nint main() { const char s[] = "0.5"; double v; fast_float::from_chars(s, s + 3, v); return v != 0.5; }\n' ;;
    libfuzzer) command -v "${CLANG:-clang}" >/dev/null &&
               CC=${CLANG:-clang} compiles c 'int LLVMFuzzerTestOneInput(const char *d, long n) { (void)d; (void)n; return 0; }\n' -fsanitize=fuzzer ;;
    *) command -v "$1" >/dev/null ;;
  esac
}

# Debian's clang runtime package carries clang's major version (libclang-rt-14-dev on
# Debian 12); older releases ship the runtime inside clang itself.
debian_name() {
  if [ "$1" = libclang-rt-dev ]; then
    local v
    v=$("${CLANG:-clang}" --version 2>/dev/null | sed -n 's/.*clang version \([0-9]*\).*/\1/p' | head -1)
    [ -n "$v" ] && apt-cache show "libclang-rt-$v-dev" >/dev/null 2>&1 && echo "libclang-rt-$v-dev"
  else
    echo "$1"
  fi
}

missing_names() { # KIND: the probes of that kind that fail
  local name kind pkgs what
  while IFS='|' read -r name kind pkgs what; do
    [ "$kind" = "$1" ] || continue
    have "$name" || echo "$name"
  done < <(needs)
}
field() { needs | awk -F'|' -v n="$1" -v f="$2" '$1 == n { print $f }'; }

req=$(missing_names required) opt=$(missing_names optional)
total=$(needs | wc -l)
if [ -z "$req$opt" ]; then echo "deps: all $total needs present"; exit 0; fi

# Install what is missing, where that is possible.
sudo=none
if [ "${DEPS_INSTALL:-yes}" != no ] && command -v apt-get >/dev/null; then
  if [ "$(id -u)" -eq 0 ]; then sudo=""
  elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then sudo=sudo; fi
fi
if [ "$sudo" != none ]; then
  pkgs=()
  for n in $req $opt; do for p in $(field "$n" 3); do p=$(debian_name "$p") && pkgs+=("$p"); done; done
  mapfile -t pkgs < <(printf '%s\n' "${pkgs[@]}" | sort -u)
  echo "deps: installing ${pkgs[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq || echo "deps: apt-get update failed; trying the install anyway"
  # Required first, on their own, so that an optional package apt cannot find never
  # stops them; then each optional package alone.
  rpkgs=$(for n in $req; do field "$n" 3; done | tr ' ' '\n' | sort -u)
  # shellcheck disable=SC2086
  [ -z "$rpkgs" ] || $sudo apt-get install -y -qq --no-install-recommends $rpkgs ||
    echo "deps: apt-get could not install $(echo $rpkgs)"
  for n in $opt; do
    for p in $(field "$n" 3); do
      p=$(debian_name "$p") || continue
      $sudo apt-get install -y -qq --no-install-recommends "$p" >/dev/null 2>&1 ||
        echo "deps: apt-get could not install $p (optional)"
    done
  done
  req=$(missing_names required) opt=$(missing_names optional)
else
  why="apt-get is not on PATH"
  if [ "${DEPS_INSTALL:-yes}" = no ]; then why="DEPS_INSTALL=no"
  elif command -v apt-get >/dev/null; then why="not root, and sudo asks for a password"; fi
  echo "deps: installing nothing ($why)"
fi

for n in $opt; do
  echo "deps: skipped (optional, not found): $n, for $(field "$n" 4) [Debian: $(field "$n" 3)]"
done
for n in $req; do
  echo "deps: MISSING (required): $n, $(field "$n" 4) [Debian: $(field "$n" 3)]" >&2
done
if [ -n "$req" ]; then
  echo "deps: install the missing libraries (or set PKG_CONFIG_PATH so pkg-config finds them), then run make again" >&2
  exit 1
fi
echo "deps: every required library present"
exit 0
