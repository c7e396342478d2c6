// A sweep on a Slurm cluster: a job array whose task k runs shard k/N of
// the sweep (k from SLURM_ARRAY_TASK_ID, its threads from
// SLURM_CPUS_PER_TASK), and a merge job that runs after the whole array
// (afterany: also when tasks failed or ran out of time, so that what
// exists is merged and the missing points are listed).
//
// DIR holds everything:
//   sweep.sbatch, merge.sbatch   the two job scripts (sbatch can submit them again)
//   shards/shard_K.{csv,json,journal}  each task's table and journal
//   logs/sweep_<array job>_<K>.out, logs/merge_<job>.out
//   table.{csv,json}             the merged table
//   table_runs/point_N           with keep_runs: each point's run directory,
//                                whichever task ran it (sweep --keep-runs)
// The shards' journals are created (or checked) when the scripts are
// written, so DIR cannot mix two sweeps and `sweep --status DIR` works
// from the start. Submitting the same sweep into the same DIR again
// (with the same array size) runs only the points not yet recorded.
#pragma once

#include <string>

#include "sim/batch/sweep.h"

namespace ipmc {

struct SlurmOptions {
  std::string dir;          // DIR above; no spaces or quotes (#SBATCH lines cannot hold them)
  int array_size = 0;       // tasks, [1, points]; 0: one per point, at most kDefaultMaxArrayTasks
  std::string partition;    // empty: the cluster's default partition
  std::string time_limit;   // per task, in Slurm's format; empty: the partition's default
  int cpus_per_task = 1;    // >= 1; each task runs this many points at once
};

// Slurm's default MaxArraySize is 1001 (task ids 0..1000).
constexpr int kDefaultMaxArrayTasks = 1000;

// Minutes of a Slurm time limit: "M", "M:S", "H:M:S", "D-H", "D-H:M",
// "D-H:M:S" (seconds round up), or "INFINITE" / "UNLIMITED" (-1). Throws
// std::invalid_argument naming `command` and --time unless it is one of
// these and > 0.
long ParseSlurmTimeLimit(const std::string& text, const std::string& command = "sweep");

// The checks every job of `command` (sweep, optimize) takes: CPUs per
// task, time limit, partition name (std::invalid_argument, one line).
void CheckSlurmOptions(const SlurmOptions& options, const std::string& command);
// The absolute path, which a job script's #SBATCH line can hold; throws
// std::invalid_argument naming it if it has a space, quote, backslash or %.
std::string SlurmScriptPath(const std::string& path, const std::string& command);
// The #SBATCH lines of the partition and the time limit.
std::string SlurmCommonDirectives(const SlurmOptions& options);

// The job, resolved: absolute paths, the number of tasks.
struct SlurmSweep {
  std::string program;     // the ipmc-swim executable
  std::string sweep_path;  // the sweep file
  std::string dir;
  int tasks = 0;
  int points = 0;
  bool keep_runs = false;  // each task keeps its points' runs in RunsDir()
  SlurmOptions options;

  std::string ArrayScriptPath() const { return dir + "/sweep.sbatch"; }
  std::string MergeScriptPath() const { return dir + "/merge.sbatch"; }
  std::string ShardPrefix(int k) const { return dir + "/shards/shard_" + std::to_string(k); }
  std::string TablePrefix() const { return dir + "/table"; }
  std::string RunsDir() const { return dir + "/table_runs"; }
};

// Checks the options against the plan (std::invalid_argument, one line
// naming the option and its range) and resolves them; writes nothing.
// keep_runs (sweep --keep-runs, or keep_runs in the sweep file): the tasks
// keep their points' runs.
SlurmSweep ResolveSlurmSweep(const SweepPlan& plan, const SlurmOptions& options,
                             const std::string& program, bool keep_runs = false);

// The job scripts' text.
std::string SlurmArrayScript(const SlurmSweep& job);
std::string SlurmMergeScript(const SlurmSweep& job);

// Creates DIR, shards/ and logs/, creates or checks every shard's journal
// (std::runtime_error naming it if one records another sweep, before
// anything is written) and writes both scripts (atomically).
void WriteSlurmJob(const SlurmSweep& job, const SweepPlan& plan);

// The full path of `program` on PATH, or "" if it is not there.
std::string FindOnPath(const std::string& program);

// Throws std::runtime_error (one line) unless sbatch is on the PATH.
void CheckSbatchOnPath(const std::string& command = "sweep");

struct SlurmJobIds {
  std::string array;
  std::string merge;
};

// Submits the array, then the merge job with --dependency=afterany:<array>,
// through `sbatch` (found on PATH; SLURM_CONF and the rest of the
// environment pass on to it). Throws std::runtime_error with sbatch's own
// message if it is missing or refuses; if the merge job is refused the
// array is cancelled (scancel), so nothing stays submitted.
SlurmJobIds SubmitSlurmJob(const SlurmSweep& job);
// The same for any array script and its merge script.
SlurmJobIds SubmitSlurmScripts(const std::string& array_script, const std::string& merge_script,
                               const std::string& command);

}  // namespace ipmc
