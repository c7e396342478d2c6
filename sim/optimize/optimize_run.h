// `optimize` as both front ends run it (docs/OPTIMIZE.md): its option
// table, the checks before the first run, the evaluations (each one
// closed-loop run of the design, by the sweep's point runner), the
// journal that makes it resumable, and the outputs.
//
//   ipmc-swim optimize OPT.toml --out DIR [--jobs N] [--resume]
//   ipmc_swim.optimize(OPT, out=DIR, jobs=N, resume=True)
//
// Outputs in DIR, written when the optimisation is done (each file whole
// or not at all): history.csv (every evaluation), convergence.csv and
// convergence.png (best-so-far against evaluation, one curve per start),
// result.json (the best design, its metrics, the stop reasons) and best/
// (the best design's run outputs: timeseries.csv, states.csv,
// summary.json). DIR/optimize.journal records every evaluation the moment
// it is done, its inputs bit for bit (hex floats) and its results; with
// resume, an evaluation whose inputs a record holds is taken from it, so
// that a stopped optimisation goes on along the same path to the same
// files. The result does not depend on jobs (the starts run in parallel,
// each its own NLopt instance).
//
// With start K only that start runs and only the journal is written (one
// task of optimize --slurm, sim/optimize/optimize_slurm.h); with journals
// FOLDER an evaluation that FOLDER/start_K/optimize.journal records is
// taken from there (and recorded in DIR's journal), so that the merge of
// the tasks' journals writes the files one local run writes.
#pragma once

#include <functional>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/io/option_table.h"
#include "sim/optimize/optimize_file.h"

namespace ipmc {

struct OptimizeCommand {
  std::string file;   // the OPT file (TOML)
  std::string out;    // DIR
  int jobs = 1;       // default: the CPUs this process may use
  bool resume = false;
  int start = -1;        // >= 0: run only this start, recording it in the journal
  std::string journals;  // a folder of start_K/optimize.journal to take evaluations from
  OptimizeCommand();
};

const OptionTable<OptimizeCommand>& OptimizeOptionTable();

struct OptimizePlan {
  OptimizeConfig config;
  std::string out;
  std::string journal;  // DIR/optimize.journal
  int jobs = 1;
  bool resume = false;
  std::optional<int> only_start;           // run this start alone; write only the journal
  std::vector<std::string> start_journals;  // read-only journals to take evaluations from
};

// The journal of start K in a folder of per-start runs (optimize --slurm's
// DIR/starts): FOLDER/start_K/optimize.journal.
std::string StartJournalPath(const std::string& folder, int start);

// Reads the OPT file and checks the options and DIR (writable; without
// resume, no journal there already): FieldError naming the field (jobs,
// out, resume) or the OPT file's field; nothing is written.
OptimizePlan PlanOptimizeCommand(const OptimizeCommand& command);

struct OptimizeProgress {
  int done = 0;           // evaluations so far, this one included
  int start = 0;
  int evaluation = 0;     // within the start, 0-based
  bool from_journal = false;
  bool ok = true;
  bool feasible = false;
  double objective = 0.0;
  std::string error;
  std::vector<double> x;  // the design keys' values (OptimizeConfig::Keys)
};

struct OptimizeHooks {
  // After each evaluation, one call at a time, from the worker threads.
  std::function<void(const OptimizeProgress&)> on_evaluation;
  // Asked before each run; once true, no run starts (the running finish).
  std::function<bool()> stop_requested;
  // >= 0: stop once this many runs (not taken from the journal) started
  // (tests of resume).
  int stop_after_runs = -1;
};

struct OptimizeOutcome {
  bool stopped = false;        // nothing written but the journal
  bool single_start = false;   // only_start ran to its end: the journal is the output
  nlohmann::ordered_json result;  // result.json's content (when not stopped)
  int evaluations = 0;
  int resumed = 0;             // of them, taken from the journal
};

// Runs the plan and, unless stopped, writes the outputs. Throws
// std::runtime_error for a journal of another problem or an output that
// cannot be written.
OptimizeOutcome RunOptimizeCommand(const OptimizePlan& plan, const OptimizeHooks& hooks = {});

// Creates or checks the journals of the plan's optimisation at `paths`:
// every one is checked before any is created (std::runtime_error naming
// one that records another optimisation or is in use).
void CheckOptimizeJournals(const OptimizePlan& plan, const std::vector<std::string>& paths);

// One line for an evaluation's progress on stderr.
std::string OptimizeProgressLine(const OptimizePlan& plan, const OptimizeProgress& progress);

}  // namespace ipmc
