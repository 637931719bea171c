#!/usr/bin/env bash
# Installs the Debian 12 packages plucker needs to build, test and run. Idempotent: packages that
# are already installed are skipped, and apt is not touched when nothing is missing.
set -euo pipefail
packages=(
  build-essential cmake ccache pkg-config
  libeigen3-dev libceres-dev
  libyaml-cpp-dev libcli11-dev libnanoflann-dev robin-map-dev nlohmann-json3-dev libtbb-dev
  libopencv-dev libopencv-contrib-dev  # images, line detectors and descriptors (vision, io)
  librosbag-storage-dev libsensor-msgs-dev  # ROS 1 bags without ROS (bag)
  libsqlite3-dev  # ROS 2 .db3 bags (bag)
  libdeflate-dev  # the fast 8-bit gray PNG read (io/png_gray.h)
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-14 libclang-rt-14-dev  # libFuzzer targets (scripts/fuzz.sh)
  pybind11-dev python3-dev python3-numpy  # the plucker Python package (python/)
  python3-pytest mypy  # its tests and the type check of its stubs
)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install_deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
