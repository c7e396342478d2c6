// Running a sweep's points (or one shard of them) on a pool of threads.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "sim/batch/sweep_file.h"
#include "sim/batch/sweep_table.h"

namespace ipmc {

// Part i of n (1 <= i <= n) of a sweep: the points with index % n == i - 1.
struct SweepShard {
  int index = 1;
  int count = 1;
};
// Reads "i/n"; throws FieldError naming the field shard.
SweepShard ParseSweepShard(const std::string& text);

struct SweepProgress {
  int done = 0;   // points finished, this one included
  int total = 0;  // points to run (in this shard)
  int point = 0;  // the index of the point just finished
  bool ok = true;
  std::string error;
  double elapsed_s = 0.0;
  const std::vector<std::string>* row = nullptr;  // the point's row, as in the table
};

struct SweepOptions {
  int jobs = 1;  // threads; >= 1
  SweepShard shard;
  // Called after each point, one call at a time, from the worker threads.
  std::function<void(const SweepProgress&)> on_point_done;
  // Rows of points that finished before (by point index): not run again,
  // copied into the table as they are.
  const std::map<int, std::vector<std::string>>* finished = nullptr;
  // Asked, from the worker threads, before each point starts; once it
  // returns true no further point starts.
  std::function<bool()> stop_requested;
  // Non-empty: each point that runs also writes its run's outputs
  // (sim/runs/output.h: timeseries.csv, states.csv, summary.json, whose
  // inputs name the sweep file and the point) into RUNS_DIR/point_N, N the
  // point's index, so that any point can be plotted, filmed or run again;
  // a point whose files cannot be written fails with that error.
  std::string runs_dir;
};

// The folder of point `index`'s run under runs_dir.
std::string SweepPointRunDir(const std::string& runs_dir, int index);
// Where `sweep --keep-runs` (or keep_runs in the sweep file) keeps the runs
// of a sweep writing PREFIX.csv: PREFIX_runs.
std::string SweepRunsDir(const std::string& out_prefix);

// Runs the shard's points on options.jobs threads (SimulateScenario per
// point), the longest runs (cycles / frequency / time step) first. The
// rows, in index order, do not depend on the number of jobs. Points in
// options.finished are not run; progress counts only the points run. If
// stop_requested stopped the sweep, the table holds the points finished
// by then (fewer rows than the shard has points). Throws
// std::invalid_argument for bad options only.
SweepTable RunSweep(const SweepPlan& plan, const SweepOptions& options);

}  // namespace ipmc
