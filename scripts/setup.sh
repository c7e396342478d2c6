#!/usr/bin/env bash
# Installs the Debian 12 packages ipmc-swim needs (only those missing) and
# builds the project, in Release (build/) or with the sanitizers
# (build-sanitize/). Sourced by ./run.sh, ./test.sh, scripts/sanitize.sh,
# scripts/soak.sh and .ci/run.
set -euo pipefail

IPMC_PACKAGES=(
  build-essential cmake pkg-config ccache
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

ipmc_jobs() {
  nproc 2>/dev/null || echo 2
}

# Configures BUILD_DIR for the tree at ROOT (further arguments go to
# cmake), compiling through ccache when it is installed. CCACHE_BASEDIR is
# the tree's root, so the cache holds paths relative to it and serves a
# clone of the tree in any other folder of this machine: the objects do
# not depend on where the tree is (only sim/core/data_paths.cc and
# tests/test_paths.cc hold its path).
ipmc_configure() {
  local root="$1" build="$2"
  shift 2
  local launcher=()
  if command -v ccache >/dev/null 2>&1; then
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  export CCACHE_BASEDIR="$root"
  cmake -S "$root" -B "$build" "${launcher[@]}" "$@" >/dev/null
}

ipmc_build() {
  local root="$1"
  ipmc_configure "$root" "$root/build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$root/build" -j "$(ipmc_jobs)"
}

# ASan + UBSan (including float-cast-overflow) in build-sanitize/, at
# -O1 -g1: line tables for the reports, and a build about half as long as
# -O2 -g. The debug information names the tree's root "." so that the
# cache serves it to another clone too. TARGET (default all):
# sanitize_tests builds only what the tests labelled `sanitize` run.
ipmc_build_sanitized() {
  local root="$1"
  local target="${2:-all}"
  local flags="-O1 -g1 -DNDEBUG -fdebug-prefix-map=$root=."
  ipmc_configure "$root" "$root/build-sanitize" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$flags" -DCMAKE_C_FLAGS_RELWITHDEBINFO="$flags" \
    -DIPMC_SWIM_SANITIZE=ON -DIPMC_SWIM_BUILD_BENCH=OFF
  cmake --build "$root/build-sanitize" -j "$(ipmc_jobs)" --target "$target"
}

# Runs ctest in BUILD_DIR, as many tests at once as there are CPUs
# (further arguments go to ctest).
ipmc_ctest() {
  local build="$1"
  shift
  (cd "$build" && ctest --output-on-failure -j "$(ipmc_jobs)" "$@")
}

# ipmc_ctest in ROOT/build-sanitize: a leak, a read or write out of bounds
# or undefined behaviour ends the test that meets it.
ipmc_ctest_sanitized() {
  local root="$1"
  shift
  (
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1"
    export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    ipmc_ctest "$root/build-sanitize" "$@"
  )
}
