#!/usr/bin/env bash
# Builds the project with AddressSanitizer and UndefinedBehaviorSanitizer
# (including float-cast-overflow) into build-sanitize/ and runs there the
# tests labelled `sanitize` (tests/CMakeLists.txt: the ones that exercise
# memory and concurrency), or with --all the whole suite. Further
# arguments go to ctest (for example -R Journal).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/setup.sh"
selection=(-L sanitize)
target=sanitize_tests
if [ "${1:-}" = "--all" ]; then
  selection=()
  target=all
  shift
fi
ipmc_install_packages
ipmc_build_sanitized "$root" "$target"
ipmc_ctest_sanitized "$root" "${selection[@]}" "$@"
