#!/usr/bin/env bash
# Runs the whole plain suite several times in a row (5 by default) and the
# sanitized one (the tests labelled `sanitize`, as .ci/run does) twice, and
# prints one line per round and a closing one:
#   soak: plain round K of N: P passed, F failed (S s)
#   soak: R rounds, F with a failure
# A failing round also names its failed tests; every round's ctest output
# is kept in build/soak/. Builds build/ and build-sanitize/ first (cached).
#
#   scripts/soak.sh [--rounds N] [--sanitized-rounds N] [--beside-build]
#                   [-- CTEST_ARGUMENTS]
#
# --beside-build: during the first plain round, a cold build of the tree
# (scratch folder, compiler cache off) runs beside the tests, as on a
# shared machine. CTEST_ARGUMENTS go to every round (for example
# -R 'concurren|journal' to soak a few tests). Exits 1 if a round failed.
# Run no other ctest in build/ or build-sanitize/ meanwhile: the tests of
# one build share its temporary folder, which each run empties first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/setup.sh"

rounds=5
sanitized_rounds=2
beside_build=0
while [ "$#" -gt 0 ]; do
  case "$1" in
    --rounds) rounds="$2"; shift 2 ;;
    --sanitized-rounds) sanitized_rounds="$2"; shift 2 ;;
    --beside-build) beside_build=1; shift ;;
    --) shift; break ;;
    *) echo "soak: unknown argument $1 (see the top of $0)" >&2; exit 2 ;;
  esac
done
ctest_args=("$@")
logs="$root/build/soak"
failed_rounds=0
all_rounds=0

# A cold build in a scratch folder, in the background of its own process
# group; prints the group's id.
start_beside_build() {
  local scratch="$1"
  setsid bash -c 'CCACHE_DISABLE=1 cmake -S "$1" -B "$2" -DCMAKE_BUILD_TYPE=Release \
    >/dev/null && CCACHE_DISABLE=1 cmake --build "$2" -j "$3"' \
    beside "$root" "$scratch" "$(ipmc_jobs)" >"$logs/beside-build.log" 2>&1 &
  echo $!
}

# One round: KIND (plain or sanitized), its number, the ctest output's file.
round() {
  local kind="$1" number="$2" of="$3"
  local log="$logs/$kind-$number.log" start=$SECONDS status=0
  if [ "$kind" = plain ]; then
    ipmc_ctest "$root/build" "${ctest_args[@]}" >"$log" 2>&1 || status=$?
  else
    ipmc_ctest_sanitized "$root" -L sanitize "${ctest_args[@]}" >"$log" 2>&1 || status=$?
  fi
  local total failed
  total=$(sed -n 's/.* tests failed out of \([0-9]*\).*/\1/p' "$log" | tail -1)
  failed=$(sed -n 's/.*, \([0-9]*\) tests failed out of.*/\1/p' "$log" | tail -1)
  if [ -z "$total" ]; then  # ctest itself failed (no tests, a build missing)
    total=0
    failed=1
  fi
  echo "soak: $kind round $number of $of: $((total - failed)) passed, $failed failed" \
    "($((SECONDS - start)) s)"
  all_rounds=$((all_rounds + 1))
  if [ "$status" -ne 0 ] || [ "$failed" -ne 0 ]; then
    failed_rounds=$((failed_rounds + 1))
    sed -n '/The following tests FAILED:/,$p' "$log" | grep -E '^\s+[0-9]+ - ' || true
    echo "soak: the round's output: $log"
  fi
}

ipmc_build "$root" >/dev/null
mkdir -p "$logs"
beside=""
if [ "$beside_build" = 1 ]; then
  scratch="$(mktemp -d)"
  beside="$(start_beside_build "$scratch")"
  echo "soak: a cold build runs beside plain round 1 ($scratch)"
fi
for ((k = 1; k <= rounds; k++)); do
  round plain "$k" "$rounds"
  if [ -n "$beside" ]; then
    kill -- "-$beside" 2>/dev/null || true
    wait "$beside" 2>/dev/null || true
    rm -rf "$scratch"
    beside=""
  fi
done
if [ "$sanitized_rounds" -gt 0 ]; then
  ipmc_build_sanitized "$root" >/dev/null
fi
for ((k = 1; k <= sanitized_rounds; k++)); do
  round sanitized "$k" "$sanitized_rounds"
done
echo "soak: $all_rounds rounds, $failed_rounds with a failure"
[ "$failed_rounds" -eq 0 ]
