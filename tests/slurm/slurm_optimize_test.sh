#!/usr/bin/env bash
# An optimisation on the one-node cluster of local_cluster.sh (started by
# the CTest fixture slurm_cluster): 2 starts of 4 evaluations submitted with
# `ipmc-swim optimize --slurm` as a 2-task job array and a merge job, the
# merge waited for, and its files compared byte for byte with a local
# --jobs 2 run of the same optimisation.
#
#   tests/slurm/slurm_optimize_test.sh STATE_DIR IPMC_SWIM SOURCE_DIR WORK_DIR
set -euo pipefail
state="$1" ipmc="$2" source_dir="$3" work="$4"
export PATH="$PATH:/usr/sbin:/sbin"

# shellcheck source=tests/slurm/test_lib.sh
source "$(dirname "$0")/test_lib.sh"
load_cluster_env "$state"

rm -rf "$work"
mkdir -p "$work"
array="" merge=""
cleanup() {
  # Whatever happened: no job of this test stays queued or running.
  [ -n "$array" ] && scancel "$array" >/dev/null 2>&1
  [ -n "$merge" ] && scancel "$merge" >/dev/null 2>&1
  return 0
}
trap cleanup EXIT

# Two short cycles (0.5 Hz at a 0.5 ms step) per evaluation: L1 and L2 free.
cat >"$work/fast.toml" <<EOT
model = "$source_dir/models/flagellum3.xml"
cycles = 1
timestep_s = 5e-4
[waveform]
frequency_Hz = 0.5
EOT
cat >"$work/opt.toml" <<'EOT'
base = "fast.toml"
[set]
cycles = 2
metrics.from_cycle = 2
link_lengths_mm = [10.0, 10.0, 10.0]
[[variable]]
key = "link_lengths_mm[0]"
lower = 8.0
upper = 14.0
initial = 10.0
[[variable]]
key = "link_lengths_mm[1]"
lower = 7.0
upper = 12.0
initial = 10.0
[sum]
key = "link_lengths_mm[2]"
total = 30.0
lower = 6.0
upper = 14.0
[objective]
metric = "last_cycle_com_along_mm"
sense = "maximize"
[algorithm]
name = "cobyla"
max_evaluations = 4
multistart = 1
EOT

"$ipmc" optimize "$work/opt.toml" --jobs 2 --out "$work/local" >"$work/local.out" 2>&1 ||
  fail "local optimize: $(cat "$work/local.out")"

submitted=$("$ipmc" optimize "$work/opt.toml" --out "$work/cluster" --slurm --time 5 2>&1) ||
  fail "optimize --slurm: $submitted"
echo "$submitted"
array=$(sed -n 's/^submitted job array \([0-9]*\) and merge job \([0-9]*\) .*/\1/p' <<<"$submitted")
merge=$(sed -n 's/^submitted job array \([0-9]*\) and merge job \([0-9]*\) .*/\2/p' <<<"$submitted")
[ -n "$array" ] && [ -n "$merge" ] || fail "no job ids in: $submitted"

wait_ended "$merge" 450
[ "$(job_state "$array")" = "COMPLETED " ] || fail "array tasks: $(job_state "$array") ($(cat "$work"/cluster/logs/optimize_* 2>&1))"
[ "$(job_state "$merge")" = "COMPLETED " ] || fail "merge job: $(job_state "$merge") ($(cat "$work"/cluster/logs/merge_* 2>&1))"

for k in 0 1; do
  grep -q "^start $k: 4 evaluations (0 from the journal)" "$work"/cluster/logs/optimize_*_"$k".out ||
    fail "task $k did not run its start: $(cat "$work"/cluster/logs/optimize_*_"$k".out)"
done
grep -q "8 evaluations (8 from the journal)" "$work"/cluster/logs/merge_*.out ||
  fail "the merge ran evaluations again: $(cat "$work"/cluster/logs/merge_*.out)"
for file in history.csv convergence.csv convergence.png result.json best/summary.json best/timeseries.csv best/states.csv; do
  cmp "$work/local/$file" "$work/cluster/$file" || fail "the cluster's $file differs from the local run's"
done
rm -rf "$work"
echo "PASS: 2 starts through a 2-task Slurm array and a merge give the local --jobs 2 files byte for byte"
