#!/usr/bin/env bash
# Installs every Debian 12 package that stickslip's build, tests, examples and plots need.
# Idempotent: when everything is present it changes nothing. Needs root (or sudo) to install.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev libspectra-dev libgmsh-dev
  libyaml-cpp-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  calculix-ccx gnuplot-nox clang-format
  libopenblas0-pthread time
  libopenmpi-dev openmpi-bin
  libpetsc-real-dev libslepc-real-dev
  python3-numpy python3-scipy python3-matplotlib python3-vtk9 python3-pandas zlib1g-dev
  python3-dev pybind11-dev python3-pytest
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} Debian packages present"
  exit 0
fi
echo "setup: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update
"${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
