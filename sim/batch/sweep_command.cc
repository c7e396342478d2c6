#include "sim/batch/sweep_command.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <utility>

#include "sim/base/error.h"
#include "sim/batch/cpu_affinity.h"
#include "sim/batch/sweep_grow.h"
#include "sim/io/columns.h"
#include "sim/io/files.h"
#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

constexpr char kSweep[] = "sweep";
constexpr char kMerge[] = "merge";

OptionInfo FormatsInfo(const std::string& what) {
  OptionInfo formats{"formats", "", "csv, mat, h5 (hdf5); repeatable or comma-separated",
                     "Also write " + what + " (mat: MATLAB/Octave; h5: HDF5)"};
  formats.aliases = {"format"};
  return formats;
}

OptionTable<SweepCommand> MakeSweepOptions() {
  OptionTable<SweepCommand> table(
      kSweep, "Run a scenario over a grid or list of overrides (a sweep file, TOML)");
  OptionInfo sweep{"sweep", "", "a TOML file", "Sweep file"};
  sweep.positional = true;
  table.AddPath(sweep, [](SweepCommand& c) -> std::string& { return c.sweep; });
  OptionInfo jobs{"jobs", "", ">= 1", "Points run in parallel"};
  jobs.default_text = "the CPUs this process may use";
  table.Add<int>(jobs, [](SweepCommand& c) -> int& { return c.jobs; });
  table.Add<std::string>({"shard", "", "i/n with 1 <= i <= n",
                          "Run part i of n: the points with index % n == i - 1"},
                         [](SweepCommand& c) -> std::string& { return c.shard; });
  OptionInfo out{"out", "", "a file name prefix, not a folder",
                 "Writes PREFIX.csv and PREFIX.json; records each point in PREFIX.journal "
                 "(resume; one sweep per prefix at a time)"};
  out.aliases = {"o"};
  table.AddPath(out, [](SweepCommand& c) -> std::string& { return c.out; });
  table.Add<std::vector<std::string>>(
      FormatsInfo("the table as PREFIX.mat or PREFIX.h5 (a group per point)"),
      [](SweepCommand& c) -> std::vector<std::string>& { return c.formats; });
  table.Add<bool>({"keep_runs", "", "",
                   "Keep each point's run directory (timeseries.csv, states.csv, summary.json) "
                   "in PREFIX_runs/point_N, to plot, film or run again; also keep_runs = true in "
                   "the sweep file"},
                  [](SweepCommand& c) -> bool& { return c.keep_runs; });
  table.AddPath({"runs_dir", "", "a folder",
                 "Where keep_runs keeps the runs (RUNS_DIR/point_N) instead of PREFIX_runs; the "
                 "shards of one sweep may share it (sweep --slurm gives them DIR/table_runs)"},
                [](SweepCommand& c) -> std::string& { return c.runs_dir; });
  OptionInfo other{"resume_other_version", "", "",
                   "Resume a journal that another ipmc-swim version wrote (its points may differ "
                   "from this version's)"};
  table.Add<bool>(other, [](SweepCommand& c) -> bool& { return c.resume_other_version; });
  return table;
}

OptionTable<MergeCommand> MakeMergeOptions() {
  OptionTable<MergeCommand> table(kMerge, "Join the tables (CSV) of a sweep's shards into one");
  OptionInfo tables{"tables", "", "CSV files", "Shard tables (PREFIX.csv of each sweep --shard)"};
  tables.positional = true;
  tables.required = true;
  table.Add<std::vector<std::string>>(
      tables, [](MergeCommand& c) -> std::vector<std::string>& { return c.tables; });
  OptionInfo out{"out", "", "a file name prefix, not a folder", "Writes PREFIX.csv and PREFIX.json"};
  out.aliases = {"o"};
  out.required = true;
  table.AddPath(out, [](MergeCommand& c) -> std::string& { return c.out; });
  OptionInfo partial{"partial", "", "",
                     "Merge the tables that exist (and the journals of those that do not); list "
                     "the missing points"};
  partial.command_line_only = true;
  table.Add<bool>(partial, [](MergeCommand& c) -> bool& { return c.partial; });
  return table;
}

// A table prefix: a file name prefix whose files are none of `inputs`, in
// a folder that can be made and written.
void CheckTableOutputs(const std::string& who, const std::string& prefix,
                       const std::vector<std::string>& suffixes,
                       const std::vector<std::string>& inputs) {
  CheckTablePrefix(who, "out", prefix);
  try {
    for (const std::string& suffix : suffixes) {
      RefuseOverwritingInputs(who, "out", prefix + suffix, inputs);
    }
  } catch (const FieldError&) {
    throw;
  } catch (const std::invalid_argument& error) {
    throw FieldError(error.what(), "out", "a prefix whose files are not inputs");
  }
  RequireWritableParent(prefix);
  for (const std::string& suffix : suffixes) RequireReplaceable(prefix + suffix);
}

}  // namespace

SweepCommand::SweepCommand() : jobs(AvailableCpus()) {}

const OptionTable<SweepCommand>& SweepOptionTable() {
  static const OptionTable<SweepCommand> table = MakeSweepOptions();
  return table;
}

const OptionTable<MergeCommand>& MergeOptionTable() {
  static const OptionTable<MergeCommand> table = MakeMergeOptions();
  return table;
}

SweepCommandPlan PlanSweepCommand(const SweepCommand& command) {
  SweepCommandPlan plan;
  plan.out = command.out;
  if (!plan.out.empty()) {
    CheckTableOutputs(kSweep, plan.out, {".csv", ".json", ".journal"}, {command.sweep});
  }
  plan.shard = ParseSweepShard(command.shard);
  if (command.jobs < 1) {
    throw FieldError("sweep: jobs must be >= 1 (got " + std::to_string(command.jobs) + ")",
                     "jobs", ">= 1");
  }
  plan.jobs = command.jobs;
  plan.resume_other_version = command.resume_other_version;
  plan.formats = ParseRunFileFormats(command.formats);  // before any point runs
  plan.plan = LoadSweep(command.sweep);
  if (command.keep_runs || plan.plan.keep_runs) {
    if (plan.out.empty()) {
      throw FieldError("sweep: keep_runs needs out (the runs go to PREFIX_runs)", "keep_runs",
                       "with out");
    }
    plan.runs_dir = command.runs_dir.empty() ? SweepRunsDir(plan.out) : command.runs_dir;
    RequireWritableDirectory(plan.runs_dir);
  } else if (!command.runs_dir.empty()) {
    throw FieldError("sweep: runs_dir needs keep_runs (it is where the kept runs go)", "runs_dir",
                     "with keep_runs");
  }
  plan.points = static_cast<int>(std::count_if(
      plan.plan.points.begin(), plan.plan.points.end(), [&](const SweepPoint& point) {
        return point.index % plan.shard.count == plan.shard.index - 1;
      }));
  return plan;
}

SweepOptions SweepRunOptions(const SweepCommandPlan& plan) {
  SweepOptions options;
  options.jobs = plan.jobs;
  options.shard = plan.shard;
  options.runs_dir = plan.runs_dir;
  return options;
}

void WriteSweepOutputs(const SweepCommandPlan& plan, const SweepTable& table) {
  if (!plan.out.empty()) WriteSweepTable(plan.out, table, plan.formats);
}

SweepCommandRun::SweepCommandRun(SweepCommandPlan plan) : plan_(std::move(plan)) {
  if (!plan_.out.empty()) {
    const std::string path = plan_.out + ".journal";
    // A grown sweep (sim/batch/sweep_grow.h); not with kept runs, whose
    // folders are named by the earlier indices.
    const std::map<int, std::vector<std::string>> reused =
        plan_.runs_dir.empty() ? ReusableSweepRows(plan_.plan, plan_.shard, plan_.out)
                               : std::map<int, std::vector<std::string>>();
    if (!reused.empty()) {
      JournalFile(path, "in use by another running sweep (one sweep per output prefix at a time)")
          .Remove();
    }
    journal_ = std::make_unique<SweepJournal>(path, plan_.plan, plan_.resume_other_version);
    for (const auto& [index, row] : reused) journal_->Record(row);
    reused_ = static_cast<int>(reused.size());
    record_ = CountRecorded(plan_.plan, plan_.shard, *journal_);
  } else {
    record_.points = plan_.points;
  }
}

SweepCommandRun::~SweepCommandRun() = default;

std::string SweepCommandRun::journal_path() const {
  return journal_ ? journal_->path() : std::string();
}

SweepCommandOutcome SweepCommandRun::Run(std::function<void(const SweepProgress&)> on_point_done,
                                         std::function<bool()> stop_requested) {
  SweepOptions options = SweepRunOptions(plan_);
  options.on_point_done = std::move(on_point_done);
  options.stop_requested = std::move(stop_requested);
  SweepCommandOutcome outcome;
  if (journal_) {
    JournaledSweep run = RunJournaledSweep(plan_.plan, options, journal_.get());
    outcome.complete = run.Complete();
    outcome.table = std::move(run.table);
  } else {
    outcome.table = RunSweep(plan_.plan, options);
    outcome.complete = static_cast<int>(outcome.table.rows.size()) == plan_.points;
  }
  if (!outcome.complete) return outcome;
  const size_t status = plan_.plan.keys.size() + 1;
  const std::vector<std::vector<std::string>>& rows = outcome.table.rows;
  for (const auto& row : rows) outcome.failed += row[status] != columns::kStatusOk;
  if (!rows.empty() && outcome.failed == static_cast<int>(rows.size())) {
    // One fixed error, most likely: no table, and no journal to resume.
    if (journal_) journal_->Remove();
    throw std::runtime_error("sweep: every point failed (the first: " + rows.front()[status + 1] +
                             "); nothing written");
  }
  WriteSweepOutputs(plan_, outcome.table);
  return outcome;
}

std::string SweepOutcomeLine(const SweepCommandPlan& plan, const SweepTable& table) {
  const size_t status = plan.plan.keys.size() + 1;
  std::vector<std::vector<std::string>> ran;
  for (const std::vector<std::string>& row : table.rows) {
    if (status < row.size() && row[status] == columns::kStatusOk) ran.push_back(row);
  }
  const size_t failed = table.rows.size() - ran.size();
  std::string line = std::to_string(table.rows.size()) + " points";
  if (plan.shard.count > 1) {
    line += " (shard " + std::to_string(plan.shard.index) + "/" +
            std::to_string(plan.shard.count) + " of " + std::to_string(plan.plan.points.size()) +
            ")";
  }
  line += ": " + std::to_string(ran.size()) + " ran";
  if (failed > 0) line += ", " + std::to_string(failed) + " failed";
  const std::string warnings = WarningCountsText(table.columns, ran);
  if (!warnings.empty()) line += ", " + warnings;
  return line;
}

void CheckMergeOutputs(const MergeCommand& command) {
  CheckTableOutputs(kMerge, command.out, {".csv", ".json"}, command.tables);
}

SweepTable RunMergeCommand(const MergeCommand& command,
                           const std::function<void()>& at_safe_point) {
  CheckMergeOutputs(command);
  for (const std::string& path : command.tables) {
    std::error_code error;
    if (!std::filesystem::exists(path, error)) {
      throw std::runtime_error("merge: " + path +
                               " does not exist (a shard that did not finish? --partial merges "
                               "the tables that exist)");
    }
  }
  std::vector<SweepTable> tables;
  for (const std::string& path : command.tables) {
    tables.push_back(LoadSweepTableCsv(path));
    if (at_safe_point) at_safe_point();
  }
  const SweepTable merged = MergeSweepTables(tables, command.tables);
  if (at_safe_point) at_safe_point();
  WriteSweepTable(command.out, merged);
  return merged;
}

}  // namespace ipmc
