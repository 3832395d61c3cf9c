#!/usr/bin/env bash
# Installs the Debian packages sparselens needs that are not installed yet.
# Checks first and names what it installs; --no-install-recommends keeps OpenCV small.
set -euo pipefail
pkgs=(build-essential pkg-config clang libclang-rt-14-dev
      libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-calib3d-dev
      libopenexr-dev liblapacke-dev libcmocka-dev libproj-dev gnuplot-nox parallel valgrind
      python3)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#pkgs[@]} packages present"
  exit 0
fi
echo "deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
