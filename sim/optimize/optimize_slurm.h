// An optimisation on a Slurm cluster (docs/CLUSTER.md): a job array with
// one task per start, each running that start alone into its own journal
// (optimize --start K), and a merge job after the whole array (afterany)
// that runs the optimisation in DIR taking every evaluation the tasks
// recorded (optimize --journals DIR/starts --resume), so that DIR gets the
// files one local run writes, byte for byte; a start whose task did not
// finish is completed by the merge job.
//
// DIR holds everything:
//   optimize.sbatch, merge.sbatch    the two job scripts
//   starts/start_K/optimize.journal  start K's evaluations
//   logs/optimize_<array job>_<K>.out, logs/merge_<job>.out
//   history.csv, result.json, ...    the merge job's outputs (optimize_run.h)
// Every journal is created (or checked) when the scripts are written, so
// DIR cannot mix two optimisations; submitting again into the same DIR
// goes on from the journals.
#pragma once

#include <string>

#include "sim/batch/slurm.h"
#include "sim/optimize/optimize_run.h"

namespace ipmc {

struct OptimizeSlurmJob {
  std::string program;  // the ipmc-swim executable, absolute
  std::string file;     // the optimisation file, absolute
  std::string dir;      // --out, absolute
  int starts = 0;       // array tasks
  SlurmOptions options;  // partition and time limit (one CPU per task)

  std::string ArrayScriptPath() const { return dir + "/optimize.sbatch"; }
  std::string MergeScriptPath() const { return dir + "/merge.sbatch"; }
  std::string StartsDir() const { return dir + "/starts"; }
};

// Plans the optimisation (PlanOptimizeCommand with resume: a second
// submission goes on from the journals) and checks the Slurm options and
// paths: FieldError or std::invalid_argument, one line; writes nothing.
OptimizeSlurmJob ResolveOptimizeSlurm(const OptimizeCommand& command, const SlurmOptions& options,
                                      const std::string& program, OptimizePlan* plan);

// The job scripts' text.
std::string OptimizeSlurmArrayScript(const OptimizeSlurmJob& job);
std::string OptimizeSlurmMergeScript(const OptimizeSlurmJob& job);

// Creates DIR, starts/ and logs/, creates or checks DIR's and every
// start's journal (std::runtime_error naming one that records another
// optimisation or is in use) and writes both scripts, each atomically.
void WriteOptimizeSlurmJob(const OptimizeSlurmJob& job, const OptimizePlan& plan);

}  // namespace ipmc
