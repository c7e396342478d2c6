#!/usr/bin/env bash
# Builds the project with AddressSanitizer and UndefinedBehaviorSanitizer
# (including float-cast-overflow) into build-sanitize/ and runs the whole
# suite there. Extra arguments go to ctest (for example -R Swimming).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/setup.sh"
ipmc_install_packages
jobs=$(nproc 2>/dev/null || echo 2)
# -O1 -g1: line tables for the reports, and a build about half as long as
# -O2 -g.
cmake -S "$root" -B "$root/build-sanitize" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DIPMC_SWIM_SANITIZE=ON -DIPMC_SWIM_BUILD_BENCH=OFF >/dev/null
cmake --build "$root/build-sanitize" -j "$jobs"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1"
export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$root/build-sanitize"
ctest --output-on-failure -j "$jobs" "$@"
