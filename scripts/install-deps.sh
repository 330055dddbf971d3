#!/usr/bin/env bash
# Install every Debian package pcsim needs to build, test, plot and run design studies.
# Idempotent: packages already present are left alone. Run as root or with sudo available.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config gfortran ccache
  libeigen3-dev liblapack-dev libblas-dev
  libboost-test-dev
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
  gnuplot-nox
  libnlopt-cxx-dev
  clang libclang-rt-14-dev
  libsiconos-numerics-dev
  libginac-dev
  libopenmpi-dev openmpi-bin
  pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib python3-dev
  chromium
  ffmpeg
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
