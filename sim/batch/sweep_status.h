// Where a sweep stands, from its journals (sim/batch/journal.h): the
// points done, failed and missing, for `sweep --status`; and the merge of
// whatever shard tables and journals exist, for `merge --partial`.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "sim/batch/sweep.h"

namespace ipmc {

struct SweepStatus {
  std::string sweep;                  // the sweep file, as the journals name it
  int points = 0;                     // in the whole sweep
  std::vector<std::string> journals;  // read, sorted
  std::vector<int> done;              // status ok
  std::vector<std::pair<int, std::string>> failed;  // status error: point, error
  std::vector<int> missing;           // in no journal
};

// Reads every *.journal in `dir` and in `dir`/shards (the layout of
// sweep --slurm DIR; also sweep --out DIR/PREFIX). Throws
// std::runtime_error (one line) if there is none, or if they record
// different sweeps.
SweepStatus ReadSweepStatus(const std::string& dir);

// Point indices as ranges: {0, 1, 2, 5, 7, 8} -> "0-2, 5, 7-8".
std::string PointRanges(const std::vector<int>& points);

struct PartialMerge {
  SweepTable table;         // the rows that exist, by point index
  int points = 0;           // the sweep's size if a journal tells it, else the highest index + 1
  std::vector<int> missing;  // below `points`, in no table or journal
  std::vector<std::string> notes;  // one line per input that was not a whole table
};

// Merges the tables (PREFIX.csv) that exist; for one that does not, the
// points its journal (PREFIX.journal) recorded, if it has one (a shard
// stopped before it wrote its table). The tables and journals must be of
// one sweep (MergeSweepTables' errors, and journals with one
// fingerprint). Throws std::runtime_error (one line) if none exists.
PartialMerge MergeAvailableTables(const std::vector<std::string>& csv_paths);

}  // namespace ipmc
