#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite with CTest
# (extra arguments go to ctest).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$root/scripts/setup.sh"
ipmc_install_packages
ipmc_build "$root"
ipmc_ctest "$root/build" "$@"
