#!/bin/sh
# Installs the Debian 12 packages planetwear needs, only those missing.
# Works as root (CI) or as a user with sudo. Nothing is downloaded at build time.
set -eu
PKGS="build-essential cmake pkg-config libeigen3-dev libhdf5-dev hdf5-tools libfftw3-dev
libopenmpi-dev openmpi-bin libgtest-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libboost-dev
python3-numpy python3-h5py python3-pandas python3-matplotlib python3-scipy python3-pytest
python3-xarray python3-h5netcdf python3-setuptools python3-pip"
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -z "$missing" ]; then
  echo "install-deps: all packages present"
  exit 0
fi
echo "install-deps: installing:$missing"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: not root and no sudo; install as root:$missing" >&2; exit 1; fi
fi
$SUDO apt-get update -qq
# shellcheck disable=SC2086
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing
