#include "sim/batch/slurm.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "sim/batch/journal.h"
#include "sim/io/files.h"
#include "sim/io/process.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

constexpr char kSbatch[] = "sbatch";
constexpr char kScancel[] = "scancel";
constexpr char kTimeFormats[] = "M, M:S, H:M:S, D-H, D-H:M or D-H:M:S, or INFINITE";

bool AllDigits(const std::string& text) {
  return !text.empty() && text.size() <= 9 &&
         std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts(1);
  for (char c : text) {
    if (c == separator) {
      parts.emplace_back();
    } else {
      parts.back() += c;
    }
  }
  return parts;
}


// "1234" or "1234;cluster" (sbatch --parsable) -> "1234".
std::string JobId(const ProgramExit& run, const std::string& what) {
  const std::string said = LastLine(run.output);
  const std::string id = said.substr(0, said.find(';'));
  if (!run.ok() || !AllDigits(id)) {
    throw std::runtime_error("sbatch refused the " + what + ": " +
                             (said.empty() ? run.How() : said));
  }
  return id;
}

std::string Absolute(const std::string& path) {
  return fs::absolute(path).lexically_normal().string();
}

}  // namespace

long ParseSlurmTimeLimit(const std::string& text, const std::string& command) {
  if (text == "INFINITE" || text == "UNLIMITED") return -1;
  auto fail = [&]() -> long {
    throw std::invalid_argument(command + ": --time must be a Slurm time limit > 0 (" +
                                std::string(kTimeFormats) + "; got '" + text + "')");
  };
  const std::vector<std::string> day_parts = Split(text, '-');
  if (day_parts.size() > 2) return fail();
  const bool has_days = day_parts.size() == 2;
  const std::vector<std::string> fields = Split(day_parts.back(), ':');
  if (fields.size() > 3) return fail();
  std::vector<long> numbers;
  for (const std::string& field : fields) {
    if (!AllDigits(field)) return fail();
    numbers.push_back(std::stol(field));
  }
  long days = 0, hours = 0, minutes = 0, seconds = 0;
  if (has_days) {
    if (!AllDigits(day_parts[0])) return fail();
    days = std::stol(day_parts[0]);
    hours = numbers[0];
    if (numbers.size() > 1) minutes = numbers[1];
    if (numbers.size() > 2) seconds = numbers[2];
  } else if (numbers.size() == 3) {
    hours = numbers[0], minutes = numbers[1], seconds = numbers[2];
  } else {
    minutes = numbers[0];
    if (numbers.size() == 2) seconds = numbers[1];
  }
  const long total = ((days * 24 + hours) * 60 + minutes) + (seconds + 59) / 60;
  if (total <= 0) return fail();
  return total;
}

SlurmSweep ResolveSlurmSweep(const SweepPlan& plan, const SlurmOptions& options,
                             const std::string& program, bool keep_runs) {
  const int points = static_cast<int>(plan.points.size());
  SlurmSweep job;
  job.options = options;
  job.keep_runs = keep_runs || plan.keep_runs;
  job.points = points;
  job.tasks = options.array_size > 0 ? options.array_size
                                     : std::min(points, kDefaultMaxArrayTasks);
  if (options.array_size < 0 || job.tasks > points) {
    throw std::invalid_argument("sweep: --array-size must be in [1, " + std::to_string(points) +
                                "] (the sweep's points; got " +
                                std::to_string(options.array_size) + ")");
  }
  CheckSlurmOptions(options, "sweep");
  if (options.dir.empty()) throw std::invalid_argument("sweep: --slurm needs a directory");
  job.dir = SlurmScriptPath(options.dir, "sweep");
  job.sweep_path = SlurmScriptPath(plan.source, "sweep");
  job.program = SlurmScriptPath(program, "sweep");
  return job;
}

void CheckSlurmOptions(const SlurmOptions& options, const std::string& command) {
  if (options.cpus_per_task < 1) {
    throw std::invalid_argument(command + ": --cpus-per-task must be >= 1 (got " +
                                std::to_string(options.cpus_per_task) + ")");
  }
  if (!options.time_limit.empty()) ParseSlurmTimeLimit(options.time_limit, command);
  const bool partition_ok =
      std::all_of(options.partition.begin(), options.partition.end(), [](unsigned char c) {
        return std::isalnum(c) || c == '_' || c == '-' || c == '.' || c == ',';
      });
  if (!partition_ok) {
    throw std::invalid_argument(command + ": --partition must be a partition name (letters, "
                                "digits, _ - . and , between names; got '" + options.partition +
                                "')");
  }
}

std::string SlurmScriptPath(const std::string& path, const std::string& command) {
  const std::string absolute = Absolute(path);
  if (absolute.find_first_of(" \t\n\"'\\%") != std::string::npos) {
    throw std::invalid_argument(command + " --slurm: '" + absolute +
                                "' has a space, quote, backslash or % (the job scripts' "
                                "#SBATCH lines cannot hold them); use another path");
  }
  return absolute;
}

std::string SlurmCommonDirectives(const SlurmOptions& options) {
  std::string text;
  if (!options.partition.empty()) text += "#SBATCH --partition=" + options.partition + "\n";
  if (!options.time_limit.empty()) text += "#SBATCH --time=" + options.time_limit + "\n";
  return text;
}

std::string SlurmArrayScript(const SlurmSweep& job) {
  const std::string tasks = std::to_string(job.tasks);
  return "#!/bin/bash\n"
         "# Sweep " + job.sweep_path + " (" + std::to_string(job.points) + " points) as " +
         tasks + " array tasks: task k runs shard k/" + tasks + ".\n"
         "# Written by ipmc-swim sweep --slurm; submit with: sbatch " + job.ArrayScriptPath() +
         "\n"
         "#SBATCH --job-name=ipmc-sweep\n"
         "#SBATCH --array=1-" + tasks + "\n"
         "#SBATCH --cpus-per-task=" + std::to_string(job.options.cpus_per_task) + "\n" +
         SlurmCommonDirectives(job.options) +
         "#SBATCH --output=" + job.dir + "/logs/sweep_%A_%a.out\n"
         "set -eu\n"
         "shard=\"${SLURM_ARRAY_TASK_ID:?submit this script with sbatch}\"\n"
         "exec " + ShellQuote(job.program) + " sweep " + ShellQuote(job.sweep_path) +
         " --shard \"$shard/" + tasks + "\" --jobs \"${SLURM_CPUS_PER_TASK:-1}\" --out " +
         ShellQuote(job.dir + "/shards/shard_") + "\"$shard\"" +
         (job.keep_runs ? " --keep-runs --runs-dir " + ShellQuote(job.RunsDir()) : "") + "\n";
}

std::string SlurmMergeScript(const SlurmSweep& job) {
  std::string tables;
  for (int k = 1; k <= job.tasks; ++k) {
    tables += " \\\n  " + ShellQuote(job.ShardPrefix(k) + ".csv");
  }
  return "#!/bin/bash\n"
         "# Merges the shard tables of " + job.sweep_path + " into " + job.TablePrefix() +
         ".csv and .json,\n"
         "# listing the points of shards that did not finish. Submitted by ipmc-swim sweep "
         "--slurm\n"
         "# with --dependency=afterany on the array job.\n"
         "#SBATCH --job-name=ipmc-merge\n"
         "#SBATCH --cpus-per-task=1\n" +
         SlurmCommonDirectives(job.options) +
         "#SBATCH --output=" + job.dir + "/logs/merge_%j.out\n"
         "set -eu\n"
         "exec " + ShellQuote(job.program) + " merge --partial --out " +
         ShellQuote(job.TablePrefix()) + tables + "\n";
}

void WriteSlurmJob(const SlurmSweep& job, const SweepPlan& plan) {
  // Every existing journal is checked before anything is created.
  const std::string fingerprint = SweepFingerprint(plan);
  for (int k = 1; k <= job.tasks; ++k) {
    const std::string path = job.ShardPrefix(k) + ".journal";
    std::error_code error;
    if (!fs::exists(path, error)) continue;
    const SweepJournalHeader header = ReadSweepJournal(path).header;
    if (header.fingerprint != fingerprint) {
      throw std::runtime_error(path + ": records another sweep (" + header.sweep +
                               ", fingerprint " + header.fingerprint + "; this one: " +
                               plan.source + ", " + fingerprint +
                               "); choose another --slurm directory");
    }
  }
  EnsureDirectory(job.dir + "/shards");
  EnsureDirectory(job.dir + "/logs");
  for (int k = 1; k <= job.tasks; ++k) {
    const SweepJournal created(job.ShardPrefix(k) + ".journal", plan);
  }
  WriteFileAtomically(job.ArrayScriptPath(), SlurmArrayScript(job));
  WriteFileAtomically(job.MergeScriptPath(), SlurmMergeScript(job));
  for (const std::string& script : {job.ArrayScriptPath(), job.MergeScriptPath()}) {
    chmod(script.c_str(), 0755);
  }
}

std::string FindOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return "";
  for (const std::string& dir : Split(path, ':')) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
    if (access(candidate.c_str(), X_OK) == 0 && fs::is_regular_file(candidate)) return candidate;
  }
  return "";
}

void CheckSbatchOnPath(const std::string& command) {
  if (FindOnPath(kSbatch).empty()) {
    throw std::runtime_error(command + " --slurm: " + kSbatch +
                             " is not on the PATH (Slurm's client; --dry-run writes the "
                             "scripts without submitting)");
  }
}

SlurmJobIds SubmitSlurmJob(const SlurmSweep& job) {
  return SubmitSlurmScripts(job.ArrayScriptPath(), job.MergeScriptPath(), "sweep");
}

SlurmJobIds SubmitSlurmScripts(const std::string& array_script, const std::string& merge_script,
                               const std::string& command) {
  CheckSbatchOnPath(command);
  SlurmJobIds ids;
  ids.array = JobId(RunProgram({kSbatch, "--parsable", array_script}), "job array");
  try {
    ids.merge = JobId(RunProgram({kSbatch, "--parsable", "--dependency=afterany:" + ids.array,
                                  merge_script}),
                      "merge job");
  } catch (const std::exception& failure) {
    try {
      RunProgram({kScancel, ids.array});
    } catch (const std::exception&) {
    }
    throw std::runtime_error(std::string(failure.what()) + " (job array " + ids.array +
                             " cancelled)");
  }
  return ids;
}

}  // namespace ipmc
