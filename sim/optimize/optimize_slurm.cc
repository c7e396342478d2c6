#include "sim/optimize/optimize_slurm.h"

#include <sys/stat.h>

#include "sim/base/error.h"
#include "sim/io/files.h"
#include "sim/io/process.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "optimize";

}  // namespace

OptimizeSlurmJob ResolveOptimizeSlurm(const OptimizeCommand& command, const SlurmOptions& options,
                                      const std::string& program, OptimizePlan* plan) {
  if (command.start != -1 || !command.journals.empty()) {
    throw FieldError("optimize --slurm: start and journals are the job's own (its tasks' and "
                     "merge's); leave them out",
                     command.start != -1 ? "start" : "journals", "not with --slurm");
  }
  OptimizeCommand resuming = command;
  resuming.resume = true;
  *plan = PlanOptimizeCommand(resuming);
  CheckSlurmOptions(options, kCommand);
  OptimizeSlurmJob job;
  job.options = options;
  job.options.cpus_per_task = 1;
  job.starts = static_cast<int>(StartPoints(plan->config.Problem()).size());
  job.program = SlurmScriptPath(program, kCommand);
  job.file = SlurmScriptPath(command.file, kCommand);
  job.dir = SlurmScriptPath(command.out, kCommand);
  return job;
}

std::string OptimizeSlurmArrayScript(const OptimizeSlurmJob& job) {
  return "#!/bin/bash\n"
         "# Optimisation " + job.file + " as " + std::to_string(job.starts) +
         (job.starts == 1 ? " array task" : " array tasks") + ": task k runs start k alone into\n"
         "# " + job.StartsDir() + "/start_k/optimize.journal.\n"
         "# Written by ipmc-swim optimize --slurm; submit with: sbatch " + job.ArrayScriptPath() +
         "\n"
         "#SBATCH --job-name=ipmc-optimize\n"
         "#SBATCH --array=0-" + std::to_string(job.starts - 1) + "\n"
         "#SBATCH --cpus-per-task=1\n" +
         SlurmCommonDirectives(job.options) +
         "#SBATCH --output=" + job.dir + "/logs/optimize_%A_%a.out\n"
         "set -eu\n"
         "start=\"${SLURM_ARRAY_TASK_ID:?submit this script with sbatch}\"\n"
         "exec " + ShellQuote(job.program) + " optimize " + ShellQuote(job.file) +
         " --start \"$start\" --jobs 1 --resume --out " + ShellQuote(job.StartsDir() + "/start_") +
         "\"$start\"\n";
}

std::string OptimizeSlurmMergeScript(const OptimizeSlurmJob& job) {
  return "#!/bin/bash\n"
         "# Writes the outputs of " + job.file + " into " + job.dir + " from the array\n"
         "# tasks' journals (a start whose task did not finish runs here). Submitted by\n"
         "# ipmc-swim optimize --slurm with --dependency=afterany on the array job.\n"
         "#SBATCH --job-name=ipmc-optimize-merge\n"
         "#SBATCH --cpus-per-task=1\n" +
         SlurmCommonDirectives(job.options) +
         "#SBATCH --output=" + job.dir + "/logs/merge_%j.out\n"
         "set -eu\n"
         "exec " + ShellQuote(job.program) + " optimize " + ShellQuote(job.file) +
         " --journals " + ShellQuote(job.StartsDir()) + " --jobs 1 --resume --out " +
         ShellQuote(job.dir) + "\n";
}

void WriteOptimizeSlurmJob(const OptimizeSlurmJob& job, const OptimizePlan& plan) {
  std::vector<std::string> journals = {plan.journal};
  for (int k = 0; k < job.starts; ++k) journals.push_back(StartJournalPath(job.StartsDir(), k));
  CheckOptimizeJournals(plan, journals);
  EnsureDirectory(job.dir + "/logs");
  WriteFileAtomically(job.ArrayScriptPath(), OptimizeSlurmArrayScript(job));
  WriteFileAtomically(job.MergeScriptPath(), OptimizeSlurmMergeScript(job));
  for (const std::string& script : {job.ArrayScriptPath(), job.MergeScriptPath()}) {
    chmod(script.c_str(), 0755);
  }
}

}  // namespace ipmc
