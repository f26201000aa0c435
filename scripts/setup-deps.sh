#!/usr/bin/env bash
# Installs every Debian package rgbdi needs to build, test and run.
# Idempotent: when everything is already installed it only checks (no apt calls) and exits.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config ninja-build
  libeigen3-dev libceres-dev libopencv-dev liboctomap-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libmrpt-obs-dev libmrpt-maps-dev libmrpt-graphs-dev libmrpt-opengl-dev
  libmrpt-config-dev libmrpt-io-dev libmrpt-poses-dev libmrpt-img-dev libmrpt-system-dev
  libmrpt-hwdrivers-dev libmrpt-tclap-dev
  mrpt-apps
  librosbag-storage-dev libsensor-msgs-dev libgeometry-msgs-dev libstd-msgs-dev
  libnav-msgs-dev libtf2-msgs-dev
  pluginlib-dev librcpputils-dev libament-index-cpp-dev libroslz4-dev
  libbz2-dev zlib1g-dev libdeflate-dev nlohmann-json3-dev
  clang-format time python3 python3-numpy python3-h5py
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup-deps: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup-deps: done"
