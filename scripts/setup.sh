#!/usr/bin/env bash
# Installs the Debian 12 packages ipmc-swim needs (only those missing) and
# builds the project in Release. Sourced by ./run.sh and ./test.sh.
set -euo pipefail

IPMC_PACKAGES=(
  build-essential cmake pkg-config
  libmujoco-dev libqhull-dev libgl-dev libosmesa6-dev
  libeigen3-dev libsundials-dev libnlopt-cxx-dev libboost-math-dev
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libssl-dev
  libgtest-dev libbenchmark-dev
  libstb-dev libfftw3-dev ffmpeg gnuplot-nox poppler-utils
  libmatio-dev libhdf5-dev octave python3-scipy python3-h5py
  slurm-wlm munge
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  xvfb libglfw3-dev python3-pil python3-nbclient python3-nbformat python3-ipykernel
  python3-venv python3-pip python3-setuptools python3-wheel
)

ipmc_missing_packages() {
  local pkg
  for pkg in "${IPMC_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
      echo "$pkg"
    fi
  done
}

ipmc_install_packages() {
  local missing
  missing=$(ipmc_missing_packages)
  if [ -z "$missing" ]; then
    return 0
  fi
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
  fi
  echo "ipmc-swim: installing Debian packages:" $missing >&2
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q
  # shellcheck disable=SC2086
  $sudo apt-get install -y -q --no-install-recommends $missing
}

ipmc_build() {
  local root="$1"
  local jobs
  jobs=$(nproc 2>/dev/null || echo 2)
  cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$root/build" -j "$jobs"
}
