#!/usr/bin/env bash
# A sweep on the one-node cluster of local_cluster.sh (started by the
# CTest fixture slurm_cluster): 8 points submitted as a 4-task job array
# with `ipmc-swim sweep --slurm`, the merge job waited for, and the merged
# table compared byte for byte with a local --jobs 2 run of the same sweep.
# Then the same sweep with --keep-runs, as a 3-task array: every point's run
# directory in DIR/table_runs/point_N, whichever task ran it, the same
# files byte for byte as a local --keep-runs sweep's PREFIX_runs/point_N.
# Last, a sweep of prescribed gaits as a 2-task array against a local run.
#
#   tests/slurm/slurm_sweep_test.sh STATE_DIR IPMC_SWIM SOURCE_DIR WORK_DIR
set -euo pipefail
state="$1" ipmc="$2" source_dir="$3" work="$4"
export PATH="$PATH:/usr/sbin:/sbin"

# shellcheck source=tests/slurm/test_lib.sh
source "$(dirname "$0")/test_lib.sh"
load_cluster_env "$state"

rm -rf "$work"
mkdir -p "$work"
array="" merge="" array_runs="" merge_runs=""
cleanup() {
  # Whatever happened: no job of this test stays queued or running.
  [ -n "$array" ] && scancel "$array" >/dev/null 2>&1
  [ -n "$merge" ] && scancel "$merge" >/dev/null 2>&1
  [ -n "$array_runs" ] && scancel "$array_runs" >/dev/null 2>&1
  [ -n "$merge_runs" ] && scancel "$merge_runs" >/dev/null 2>&1
  return 0
}
trap cleanup EXIT

# Eight short runs (one 2 s wave period at a 0.5 ms step, 0.1 s each).
cat >"$work/fast.toml" <<EOF
model = "$source_dir/models/flagellum3.xml"
actuation = "distributed"
cycles = 1
timestep_s = 5e-4
[waveform]
frequency_Hz = 0.5
EOF
cat >"$work/sweep.toml" <<EOF
base = "fast.toml"
[grid]
"waveform.frequency_Hz" = [0.5, 1.0]
actuation = ["single", "distributed"]
"controller.kp" = [8.12, 4]
EOF

"$ipmc" sweep "$work/sweep.toml" --jobs 2 --out "$work/local/table" >"$work/local.out" 2>&1 ||
  fail "local sweep: $(cat "$work/local.out")"

# Submits $submit_file into $1 with the options that follow; sets $array and $merge.
submit_file="$work/sweep.toml"
submit() {
  local dir="$1" submitted
  shift
  submitted=$("$ipmc" sweep "$submit_file" --slurm "$dir" "$@" --cpus-per-task 1 --time 5 2>&1) ||
    fail "sweep --slurm: $submitted"
  echo "$submitted"
  array=$(sed -n 's/^submitted job array \([0-9]*\) and merge job \([0-9]*\) .*/\1/p' <<<"$submitted")
  merge=$(sed -n 's/^submitted job array \([0-9]*\) and merge job \([0-9]*\) .*/\2/p' <<<"$submitted")
  [ -n "$array" ] && [ -n "$merge" ] || fail "no job ids in: $submitted"
}

# Waits for $merge to end; the array's and the merge's logs are in $1/logs.
wait_done() {
  wait_ended "$merge" 450
  [ "$(job_state "$array")" = "COMPLETED " ] || fail "array tasks: $(job_state "$array") (logs: $(cat "$1"/logs/sweep_* 2>&1))"
  [ "$(job_state "$merge")" = "COMPLETED " ] || fail "merge job: $(job_state "$merge") ($(cat "$1"/logs/merge_* 2>&1))"
}

submit "$work/cluster" --array-size 4
wait_done "$work/cluster"
for k in 1 2 3 4; do
  rows=$(($(wc -l <"$work/cluster/shards/shard_$k.csv") - 1))
  [ "$rows" -eq 2 ] || fail "shard $k/4 has $rows points, expected 2 (points $((k - 1)) and $((k + 3)))"
done
cmp "$work/local/table.csv" "$work/cluster/table.csv" || fail "the cluster's table.csv differs from the local run's"
cmp "$work/local/table.json" "$work/cluster/table.json" || fail "the cluster's table.json differs from the local run's"
status=$("$ipmc" sweep --status "$work/cluster")
echo "$status"
grep -qx "done:    8 (0-7)" <<<"$status" || fail "status does not list 8 points done"
grep -qx "missing: 0" <<<"$status" || fail "status lists missing points"
echo "PASS: 8 points through a 4-task Slurm array give the local --jobs 2 table byte for byte"

# --keep-runs: a 3-task array (points 0 3 6, 1 4 7, 2 5) against a local run.
"$ipmc" sweep "$work/sweep.toml" --jobs 2 --keep-runs --out "$work/local_runs/table" \
  >"$work/local_runs.out" 2>&1 || fail "local sweep --keep-runs: $(cat "$work/local_runs.out")"
array_runs="" merge_runs=""
submit "$work/cluster_runs" --array-size 3 --keep-runs
array_runs=$array merge_runs=$merge
grep -qF -- "--keep-runs --runs-dir '$work/cluster_runs/table_runs'" "$work/cluster_runs/sweep.sbatch" ||
  fail "sweep.sbatch does not keep the runs: $(cat "$work/cluster_runs/sweep.sbatch")"
wait_done "$work/cluster_runs"
kept=$(cd "$work/cluster_runs/table_runs" && find . -type f | sort | tr '\n' ' ')
expected=""
for n in 0 1 2 3 4 5 6 7; do
  expected+="./point_$n/model.xml ./point_$n/states.csv ./point_$n/summary.json ./point_$n/timeseries.csv "
done
[ "$kept" = "$expected" ] || fail "the cluster kept: $kept; expected: $expected"
diff -r "$work/local_runs/table_runs" "$work/cluster_runs/table_runs" ||
  fail "the cluster's point run directories differ from the local --keep-runs sweep's"
cmp "$work/local_runs/table.csv" "$work/cluster_runs/table.csv" ||
  fail "the --keep-runs cluster table differs from the local run's"
echo "PASS: --keep-runs through a 3-task Slurm array keeps the 8 points' run directories, byte for byte the local sweep's"

# A sweep of prescribed gaits ([gait], sim/batch/sweep_gait.h) as a 2-task array.
cat >"$work/gait.toml" <<EOF
[gait]
model = "$source_dir/models/flagellum3.xml"
frequency_Hz = 0.5
cycles = 1
samples_per_cycle = 20
[grid]
phase_lag_rad = [0.0, 1.0, 2.0]
EOF
"$ipmc" sweep "$work/gait.toml" --jobs 2 --out "$work/local_gait/table" >"$work/local_gait.out" 2>&1 ||
  fail "local gait sweep: $(cat "$work/local_gait.out")"
submit_file="$work/gait.toml"
submit "$work/cluster_gait" --array-size 2
wait_done "$work/cluster_gait"
cmp "$work/local_gait/table.csv" "$work/cluster_gait/table.csv" ||
  fail "the cluster's gait table differs from the local run's"
cmp "$work/local_gait/table.json" "$work/cluster_gait/table.json" ||
  fail "the cluster's gait table.json differs from the local run's"
rm -rf "$work"
echo "PASS: a gait sweep through a 2-task Slurm array gives the local table byte for byte"
