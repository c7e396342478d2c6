#!/usr/bin/env bash
# The cost of going through Slurm, and of a resume, on the 8-point sweep
# of sweep_bench (the paper's scenario at 0.03 to 0.065 Hz, two cycles):
#  - points per minute of a local `sweep --jobs 2` against the same sweep
#    as a 4-task job array (one CPU per task) on the one-node cluster of
#    tests/slurm/local_cluster.sh, from `sweep --slurm` to the end of the
#    merge job;
#  - a local --jobs 2 run SIGKILLed once 4 points are recorded, plus its
#    resumed run, against an uninterrupted run; and a resume with nothing
#    left to run (reading the sweep and the journal, writing the table).
# Each measurement is repeated (default 3) and the medians are printed.
#
#   sudo bench/slurm_overhead.sh [REPEATS]    # after ./test.sh has built build/
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ipmc="$root/build/sim/ipmc-swim"
repeats="${1:-3}"
work=$(mktemp -d "${TMPDIR:-/tmp}/ipmc-slurm-bench.XXXXXX")
state="$work/cluster-state"
cleanup() {
  bash "$root/tests/slurm/local_cluster.sh" stop "$state" || true
  rm -rf "$work"
}
trap cleanup EXIT

cat >"$work/sweep.toml" <<EOF
base = "$root/scenarios/paper.toml"
[set]
cycles = 2
[grid]
"waveform.frequency_Hz" = [0.03, 0.035, 0.04, 0.045, 0.05, 0.055, 0.06, 0.065]
EOF
points=8

now() { date +%s.%N; }
calc() { awk "BEGIN { print $1 }"; }
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
records() { [ -f "$1" ] && echo $(($(wc -l <"$1") - 1)) || echo 0; }

bash "$root/tests/slurm/local_cluster.sh" start "$state"
set -a
source "$state/env"
set +a

merge_state() { scontrol -o show job "$1" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p'; }

: >"$work/local" >"$work/slurm" >"$work/whole" >"$work/killed" >"$work/nothing"
for r in $(seq "$repeats"); do
  t0=$(now)
  "$ipmc" sweep "$work/sweep.toml" --jobs 2 --out "$work/l$r/table" >/dev/null 2>&1
  t1=$(now)
  calc "$t1 - $t0" >>"$work/local"

  t0=$(now)
  out=$("$ipmc" sweep "$work/sweep.toml" --slurm "$work/s$r" --array-size 4 --cpus-per-task 1)
  merge=$(sed -n 's/^submitted job array [0-9]* and merge job \([0-9]*\) .*/\1/p' <<<"$out")
  until [ "$(merge_state "$merge")" = COMPLETED ]; do
    case "$(merge_state "$merge")" in FAILED | CANCELLED | TIMEOUT) echo "merge job $merge failed" >&2; exit 1 ;; esac
    sleep 0.05
  done
  t1=$(now)
  calc "$t1 - $t0" >>"$work/slurm"
  cmp "$work/l$r/table.csv" "$work/s$r/table.csv"

  # Uninterrupted, for the resume (the same as the local run above).
  t0=$(now)
  "$ipmc" sweep "$work/sweep.toml" --jobs 2 --out "$work/w$r/table" >/dev/null 2>&1
  t1=$(now)
  calc "$t1 - $t0" >>"$work/whole"

  t0=$(now)
  "$ipmc" sweep "$work/sweep.toml" --jobs 2 --out "$work/k$r/table" >/dev/null 2>&1 &
  pid=$!
  until [ "$(records "$work/k$r/table.journal")" -ge 4 ]; do sleep 0.01; done
  kill -KILL "$pid"
  wait "$pid" 2>/dev/null || true
  "$ipmc" sweep "$work/sweep.toml" --jobs 2 --out "$work/k$r/table" >/dev/null 2>&1
  t1=$(now)
  calc "$t1 - $t0" >>"$work/killed"
  cmp "$work/w$r/table.csv" "$work/k$r/table.csv"

  t0=$(now)
  "$ipmc" sweep "$work/sweep.toml" --jobs 2 --out "$work/k$r/table" >/dev/null 2>&1
  t1=$(now)
  calc "$t1 - $t0" >>"$work/nothing"
done

local_s=$(median <"$work/local")
slurm_s=$(median <"$work/slurm")
whole_s=$(median <"$work/whole")
killed_s=$(median <"$work/killed")
nothing_s=$(median <"$work/nothing")
printf 'medians of %d runs, %d points:\n' "$repeats" "$points"
printf '  local --jobs 2:               %6.2f s  %6.1f points/min\n' "$local_s" "$(calc "60 * $points / $local_s")"
printf '  Slurm, 4-task array + merge:  %6.2f s  %6.1f points/min  (ratio to local %.3f)\n' \
  "$slurm_s" "$(calc "60 * $points / $slurm_s")" "$(calc "$local_s / $slurm_s")"
printf '  uninterrupted --jobs 2:       %6.2f s\n' "$whole_s"
printf '  killed at 4 points + resumed: %6.2f s  (overhead %+.1f %%)\n' "$killed_s" \
  "$(calc "100 * ($killed_s / $whole_s - 1)")"
printf '  resume with nothing to run:   %6.2f s\n' "$nothing_s"
