// `sweep` and `merge` as both front ends run them (sim/batch/sweep.h
// describes sweep files and the table): their option tables, the checks
// of every output before a point runs, and the table's files.
//
//   ipmc-swim sweep SWEEP.toml --out PREFIX [--jobs N] [--shard i/n] [--format mat,h5]
//   ipmc_swim.sweep(SWEEP, out=PREFIX, jobs=N, shard="i/n", formats=[...])
//   ipmc-swim merge --out PREFIX A.csv B.csv ...
//
// The command line also keeps a resume journal (PREFIX.journal) and offers
// --slurm, --status and merge --partial (sim/cli/sweep_command.h,
// sim/cli/slurm_command.h).
#pragma once

#include <string>
#include <vector>

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
  bool resume_other_version = false;  // command line: a journal of another version
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
  int jobs = 1;
  int points = 0;  // points of the shard
};

// Throws FieldError naming the field (jobs, shard, out, formats) before
// anything runs; InputError for the sweep file.
SweepCommandPlan PlanSweepCommand(const SweepCommand& command);

// The options RunSweep takes (jobs, shard; no callbacks).
SweepOptions SweepRunOptions(const SweepCommandPlan& plan);

// Writes OUT.csv and OUT.json (and the formats' files); nothing if out is "".
void WriteSweepOutputs(const SweepCommandPlan& plan, const SweepTable& table);

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
// OUT.json; returns the merged table.
SweepTable RunMergeCommand(const MergeCommand& command);

}  // namespace ipmc
