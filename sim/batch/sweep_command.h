// `sweep` and `merge` as both front ends run them (sim/batch/sweep.h
// describes sweep files and the table): their option tables, the checks
// of every output before a point runs, and the table's files.
//
//   ipmc-swim sweep SWEEP.toml --out PREFIX [--jobs N] [--shard i/n] [--format mat,h5]
//                   [--keep-runs]
//   ipmc_swim.sweep(SWEEP, out=PREFIX, jobs=N, shard="i/n", formats=[...], keep_runs=True,
//                   resume_other_version=True)
//   ipmc-swim merge --out PREFIX A.csv B.csv ...
//
// Both front ends run a sweep with an output through SweepCommandRun: its
// journal PREFIX.journal (sim/batch/journal.h) is the sweep's lock (one
// sweep per prefix, whichever front end runs it) and its resume record (a
// sweep stopped by either front end goes on in either). The command line
// also offers --slurm, --status and merge --partial (sim/cli/sweep_command.h,
// sim/cli/slurm_command.h).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sim/batch/journal.h"
#include "sim/batch/sweep.h"
#include "sim/io/option_table.h"
#include "sim/runs/output.h"

namespace ipmc {

struct SweepCommand {
  std::string sweep;                 // the sweep file (TOML)
  int jobs = 1;                      // default: the CPUs this process may use
  std::string shard = "1/1";         // i/n
  std::string out;                   // PREFIX of PREFIX.csv and PREFIX.json
  std::vector<std::string> formats;  // besides CSV and JSON: mat, h5
  bool keep_runs = false;            // or keep_runs in the sweep file: PREFIX_runs/point_N
  std::string runs_dir;              // keep_runs's folder instead of PREFIX_runs
  bool resume_other_version = false;  // resume a journal of another version
  SweepCommand();
};

const OptionTable<SweepCommand>& SweepOptionTable();

// A sweep as planned before its first point: the sweep file read, the shard
// and formats parsed, the output prefix checked (a file name prefix whose
// files are not the sweep file, in a writable folder; "" for none).
struct SweepCommandPlan {
  SweepPlan plan;
  SweepShard shard;
  RunFileFormats formats;
  std::string out;
  std::string runs_dir;  // each point's run directory under it (keep_runs); "" for none
  int jobs = 1;
  int points = 0;  // points of the shard
  bool resume_other_version = false;
};

// Throws FieldError naming the field (jobs, shard, out, formats,
// keep_runs: it needs out, runs_dir: it needs keep_runs) before anything
// runs; InputError for the sweep file.
SweepCommandPlan PlanSweepCommand(const SweepCommand& command);

// The options RunSweep takes (jobs, shard, runs_dir; no callbacks).
SweepOptions SweepRunOptions(const SweepCommandPlan& plan);

// Writes OUT.csv and OUT.json (and the formats' files); nothing if out is "".
void WriteSweepOutputs(const SweepCommandPlan& plan, const SweepTable& table);

// What a planned sweep gave.
struct SweepCommandOutcome {
  SweepTable table;       // the shard's rows that exist, by point index
  bool complete = false;  // every point of the shard: the outputs are written
  int failed = 0;         // points whose status is not ok
};

// A planned sweep as both front ends run it. With an output prefix, the
// constructor takes the journal PREFIX.journal (creating it, or reading
// the points it holds): it throws std::runtime_error, before any point
// runs, if another sweep holds it ("in use by another running sweep"), if
// it records another sweep, or if another version wrote it (unless
// resume_other_version). A sweep that grew takes the rows of its earlier
// table instead (sim/batch/sweep_grow.h): its journal starts over with
// them. Without an output there is no journal.
class SweepCommandRun {
 public:
  explicit SweepCommandRun(SweepCommandPlan plan);
  ~SweepCommandRun();
  SweepCommandRun(const SweepCommandRun&) = delete;
  SweepCommandRun& operator=(const SweepCommandRun&) = delete;

  const SweepCommandPlan& plan() const { return plan_; }
  // The journal's path, "" without an output.
  std::string journal_path() const;
  // The shard's points and how many of them the journal held when opened.
  const ShardRecord& record() const { return record_; }
  // Points left to run.
  int ToRun() const { return record_.points - record_.recorded; }
  // Of the points recorded, those taken from the earlier table of a sweep
  // that grew (sim/batch/sweep_grow.h).
  int Reused() const { return reused_; }

  // Runs the points the journal does not hold (each recorded as it
  // finishes, before on_point_done sees it) until all are done or
  // stop_requested (asked before each point starts) returns true. Complete:
  // writes the outputs, unless every point failed: then the journal is
  // removed, nothing is written and it throws std::runtime_error "sweep:
  // every point failed (the first: ...); nothing written". Stopped: writes
  // nothing (the journal keeps the finished points). Once only.
  SweepCommandOutcome Run(std::function<void(const SweepProgress&)> on_point_done,
                          std::function<bool()> stop_requested);

 private:
  SweepCommandPlan plan_;
  std::unique_ptr<SweepJournal> journal_;
  ShardRecord record_;
  int reused_ = 0;
};

// A finished sweep's closing line: "20 points: 20 ran, 8 with warnings:
// Re > 1 (8), clamp > 25 % (5)" (with ", 1 failed" after "ran" when points
// failed, and the shard when the plan runs one; sim/runs/run_warnings.h
// counts the warnings from the table's columns).
std::string SweepOutcomeLine(const SweepCommandPlan& plan, const SweepTable& table);

struct MergeCommand {
  std::vector<std::string> tables;  // the shards' PREFIX.csv
  std::string out;                  // PREFIX of the merged table
  bool partial = false;  // command line: the tables that exist, and the journals of the others
};

const OptionTable<MergeCommand>& MergeOptionTable();

// Checks the output prefix (a file name prefix, not over a table merged,
// writable): FieldError naming out.
void CheckMergeOutputs(const MergeCommand& command);

// Checks, then merges the tables (each must exist) into OUT.csv and
// OUT.json; returns the merged table. at_safe_point, if given, is called
// after each table is read and before anything is written: a front end
// that stops there (by throwing) leaves no output.
SweepTable RunMergeCommand(const MergeCommand& command,
                           const std::function<void()>& at_safe_point = {});

}  // namespace ipmc
