#include "sim/cli/sweep_command.h"

#include "sim/cli/command.h"

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/batch/journal.h"
#include "sim/runs/run_warnings.h"
#include "sim/batch/sweep.h"
#include "sim/io/columns.h"
#include "sim/base/numbers.h"
#include "sim/cli/interrupt.h"
#include "sim/cli/slurm_command.h"
#include "sim/io/files.h"
#include "sim/io/progress_bar.h"

namespace ipmc {
namespace {

// Result columns shown on stdout (all are in the files).
constexpr const char* kShownResults[] = {columns::kMeanSpeedAlong, columns::kLastCycleComAlong,
                                         kWarningsColumn};

// Progress on stderr: a bar redrawn in place on a terminal, else one line
// per point (for logs and pipes).
class ProgressReport {
 public:
  explicit ProgressReport(bool terminal) : bar_("sweep", "runs", terminal) {}

  void Start(int total) { bar_.Start(total); }

  void operator()(const SweepProgress& p) {
    if (!bar_.terminal()) {
      if (p.ok) {
        std::fprintf(stderr, "run %d/%d done (point %d)\n", p.done, p.total, p.point);
      } else {
        std::fprintf(stderr, "run %d/%d failed (point %d): %s\n", p.done, p.total, p.point,
                     p.error.c_str());
      }
      return;
    }
    if (!p.ok) ++failed_;
    bar_.Update(p.done, failed_ > 0 ? std::to_string(failed_) + " failed" : "");
  }

  void Finish() { bar_.Finish(); }

 private:
  ProgressBar bar_;
  int failed_ = 0;
};

// A number cell at 6 significant digits; other cells as they are.
// (The table writes numbers without a '+'; a cell with one is text.)
std::string PrintedCell(const std::string& cell) {
  const std::optional<double> value = cell.empty() || cell[0] == '+' ? std::nullopt
                                                                     : ParseDouble(cell);
  return value ? FormatDouble(*value, 6) : cell;
}

// The swept values, status and speed of each row, aligned.
void PrintSummary(const SweepTable& table) {
  const std::vector<std::string>& names = table.columns;
  const size_t status =
      std::find(names.begin(), names.end(), columns::kStatus) - names.begin();
  std::vector<size_t> shown;
  for (size_t c = 0; c <= status && c < names.size(); ++c) shown.push_back(c);
  for (const char* name : kShownResults) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) shown.push_back(it - names.begin());
  }
  std::vector<size_t> width;
  for (size_t c : shown) {
    size_t w = names[c].size();
    for (const auto& row : table.rows) w = std::max(w, PrintedCell(row[c]).size());
    width.push_back(w);
  }
  auto print_row = [&](auto cell_of) {
    std::string line;
    for (size_t k = 0; k < shown.size(); ++k) {
      std::string cell = cell_of(shown[k]);
      cell.resize(width[k], ' ');
      line += (k > 0 ? "  " : "") + cell;
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    std::printf("%s\n", line.c_str());
  };
  print_row([&](size_t c) { return names[c]; });
  for (const auto& row : table.rows) print_row([&](size_t c) { return PrintedCell(row[c]); });
}

int RunSweepFile(const SweepArgs& args) {
  const SweepCommand& command = args.sweep.spec;
  if (!args.status_dir.empty()) {
    if (!command.sweep.empty()) throw std::invalid_argument("sweep: --status takes no sweep file");
    return RunSweepStatus(args.status_dir);
  }
  if (command.sweep.empty()) throw std::invalid_argument("sweep: needs a sweep file");
  if (!args.slurm.dir.empty()) return RunSlurmSubmission(args);
  if (command.out.empty()) {
    throw std::invalid_argument("sweep: --out PREFIX is required (or --slurm DIR)");
  }
  SweepCommandRun sweep(
      TranslatingFieldErrors(SweepOptionTable(), [&] { return PlanSweepCommand(command); }));
  const ShardRecord& record = sweep.record();
  const std::string& journal = sweep.journal_path();
  if (sweep.Reused() > 0) {
    std::fprintf(stderr,
                 "the sweep grew: %d of its %d points are in %s.csv (matched by their resolved "
                 "inputs) and are not run again\n",
                 sweep.Reused(), record.points, command.out.c_str());
  } else if (record.recorded > 0) {
    std::fprintf(stderr, "resuming from %s: %d of %d points done before\n", journal.c_str(),
                 record.recorded, record.points);
  }
  ProgressReport progress(StderrIsTerminal());
  progress.Start(sweep.ToRun());
  SweepCommandOutcome run;
  int stop_signal = 0;
  {
    const InterruptAtBoundary interrupt(
        "interrupted: finishing the points that are running, then stopping (Ctrl-C again stops "
        "at once; finished points stay in " + journal + ")");
    run = sweep.Run([&](const SweepProgress& p) { progress(p); },
                    [&] { return interrupt.Requested(); });
    stop_signal = interrupt.signal();
  }
  progress.Finish();
  if (!run.complete) {
    const Interrupted stop(stop_signal != 0 ? stop_signal : SIGINT, "");
    std::fprintf(stderr,
                 "ipmc-swim: interrupted by %s: stopped: %zu of %d points done, recorded in %s; "
                 "run the same command again to resume\n",
                 stop.SignalName().c_str(), run.table.rows.size(), record.points,
                 journal.c_str());
    return stop.ExitCode();
  }
  const SweepTable& table = run.table;
  const size_t status = sweep.plan().plan.keys.size() + 1;
  for (const auto& row : table.rows) {
    if (row[status] != columns::kStatusOk) {
      std::fprintf(stderr, "point %s failed: %s\n", row[0].c_str(), row[status + 1].c_str());
    }
  }
  PrintSummary(table);
  std::printf("%s; wrote %s.csv and %s.json\n", SweepOutcomeLine(sweep.plan(), table).c_str(),
              command.out.c_str(), command.out.c_str());
  return 0;
}

int RunMergeTables(const SweepArgs& args) {
  const MergeCommand& command = args.merge.spec;
  // A signal stops it before it writes; once writing, the tables are
  // written whole (each file atomically) and the merge ends.
  const InterruptAtBoundary interrupt("interrupted: stopping before the merged table is written "
                                      "(again: at once)");
  if (command.partial) {
    TranslatingFieldErrors(MergeOptionTable(), [&] { CheckMergeOutputs(command); });
    interrupt.ThrowIfRequested("nothing written");
    return RunPartialMerge(args);
  }
  const SweepTable merged = TranslatingFieldErrors(MergeOptionTable(), [&] {
    return RunMergeCommand(command, [&] { interrupt.ThrowIfRequested("nothing written"); });
  });
  std::printf("%zu points from %zu tables; wrote %s.csv and %s.json\n", merged.rows.size(),
              command.tables.size(), command.out.c_str(), command.out.c_str());
  return 0;
}

}  // namespace

void AddSweepCommands(CLI::App& app, SweepArgs& args) {
  AddSlurmOptions(AddTableCommand(app, SweepOptionTable(), args.sweep), args);
  AddTableCommand(app, MergeOptionTable(), args.merge);
}

int RunSweepCommandLine(const CLI::App&, const SweepArgs& args) {
  if (args.sweep.Chosen()) return RunSweepFile(args);
  if (args.merge.Chosen()) return RunMergeTables(args);
  return -1;
}

}  // namespace ipmc
