#include "sim/cli/slurm_command.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include "sim/batch/slurm.h"
#include "sim/io/process.h"
#include "sim/batch/sweep.h"
#include "sim/batch/sweep_status.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

// This program, as the job scripts run it.
std::string ThisProgram() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("sweep --slurm: cannot find this program's path (/proc/self/exe)");
  return self.string();
}

std::string Count(size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

void AddSlurmOptions(CLI::App* sweep, SweepArgs& args) {
  SlurmOptions& slurm = args.slurm;
  CLI::Option* dir = sweep->add_option(
      "--slurm", slurm.dir,
      "Run on Slurm: write a job array and a merge job into DIR and submit them (sbatch)");
  CLI::Option* local_only[] = {sweep->get_option("--out"), sweep->get_option("--jobs"),
                               sweep->get_option("--shard"), sweep->get_option("--runs-dir")};
  for (CLI::Option* option : local_only) dir->excludes(option);
  sweep->add_option("--array-size", slurm.array_size,
                    "Slurm: array tasks, [1, points] (default: one per point, at most " +
                        std::to_string(kDefaultMaxArrayTasks) + ")")
      ->needs(dir);
  sweep->add_option("--partition", slurm.partition, "Slurm: partition (default: the cluster's)")
      ->needs(dir);
  sweep->add_option("--time", slurm.time_limit,
                    "Slurm: time limit per task, e.g. 90, 1:30:00, 2-00 (default: the partition's)")
      ->needs(dir);
  sweep->add_option("--cpus-per-task", slurm.cpus_per_task,
                    "Slurm: CPUs per task; each task runs this many points at once")
      ->capture_default_str()
      ->needs(dir);
  sweep->add_flag("--dry-run", args.dry_run, "Slurm: write the job scripts, do not submit")
      ->needs(dir);
  CLI::Option* status = sweep->add_option(
      "--status", args.status_dir,
      "List the points done, failed and missing of the sweep in DIR (its journals)");
  status->excludes(dir);
  for (CLI::Option* option : local_only) status->excludes(option);
}

int RunSlurmSubmission(const SweepArgs& args) {
  const SweepPlan plan = LoadSweep(args.sweep.spec.sweep);
  const SlurmSweep job =
      ResolveSlurmSweep(plan, args.slurm, ThisProgram(), args.sweep.spec.keep_runs);
  if (!args.dry_run) CheckSbatchOnPath();
  WriteSlurmJob(job, plan);
  auto print_written = [&] {
    std::printf("wrote %s (%s of %s, %s each) and %s\n", job.ArrayScriptPath().c_str(),
                Count(job.tasks, "task", "tasks").c_str(),
                Count(job.points, "point", "points").c_str(),
                Count(job.options.cpus_per_task, "CPU", "CPUs").c_str(),
                job.MergeScriptPath().c_str());
  };
  if (args.dry_run) {
    print_written();
    std::printf("dry run, nothing submitted; to submit:\n"
                "  jid=$(sbatch --parsable %s) && sbatch --dependency=afterany:$jid %s\n",
                ShellWord(job.ArrayScriptPath()).c_str(), ShellWord(job.MergeScriptPath()).c_str());
    return 0;
  }
  const SlurmJobIds ids = SubmitSlurmJob(job);
  print_written();
  std::printf("submitted job array %s and merge job %s (after the array); the table goes to "
              "%s.csv\n",
              ids.array.c_str(), ids.merge.c_str(), job.TablePrefix().c_str());
  std::printf("progress: ipmc-swim sweep --status %s\n", ShellWord(job.dir).c_str());
  return 0;
}

int RunSweepStatus(const std::string& dir) {
  const SweepStatus status = ReadSweepStatus(dir);
  std::printf("%s: %s, %s\n", status.sweep.c_str(), Count(status.points, "point", "points").c_str(),
              Count(status.journals.size(), "journal", "journals").c_str());
  auto print_points = [](const char* what, const std::vector<int>& points) {
    std::printf("%-8s %zu", what, points.size());
    if (!points.empty()) std::printf(" (%s)", PointRanges(points).c_str());
    std::printf("\n");
  };
  print_points("done:", status.done);
  std::vector<int> failed;
  for (const auto& [point, error] : status.failed) failed.push_back(point);
  print_points("failed:", failed);
  for (const auto& [point, error] : status.failed) {
    std::printf("  point %d: %s\n", point, error.c_str());
  }
  print_points("missing:", status.missing);
  return 0;
}

int RunPartialMerge(const SweepArgs& args) {
  const PartialMerge merge = MergeAvailableTables(args.merge.spec.tables);
  WriteSweepTable(args.merge.spec.out, merge.table);
  for (const std::string& note : merge.notes) std::printf("%s\n", note.c_str());
  std::printf("%zu of %s merged; wrote %s.csv and %s.json\n", merge.table.rows.size(),
              Count(merge.points, "point", "points").c_str(), args.merge.spec.out.c_str(),
              args.merge.spec.out.c_str());
  if (!merge.missing.empty()) {
    std::printf("missing: %zu (%s)\n", merge.missing.size(), PointRanges(merge.missing).c_str());
  }
  return 0;
}

}  // namespace ipmc
