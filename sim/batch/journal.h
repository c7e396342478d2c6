// A sweep's journal: every point is recorded, durably, the moment it
// finishes, so that a sweep that is stopped (Ctrl-C, a killed job, a
// lost node) goes on from where it was. Running the same sweep into the
// same output again skips the recorded points; their rows are the very
// cells the uninterrupted run would have written, so the table comes out
// byte for byte the same.
//
// Format: PREFIX.journal, lines of JSON, appended and never rewritten.
//   {"ipmc_swim_sweep_journal": 2, "program_version": "0.1.0", "sweep": "sweep.toml",
//    "fingerprint": "9f0c...", "points": 12, "columns": ["point", ...]}   the header
//   {"point": 3, "row": ["3", "0.01", "ok", "", ...], "check": "5e1a..."}  one per point
// "check" is SHA-256 over the fingerprint, the point and its row: a record
// that fails it (edited by hand, pasted from another sweep, a status
// changed), or a second record of a point that differs from the first, is
// an error naming its line. A journal written by another program version
// is refused unless the caller accepts it. The journal is never opened
// through a symbolic link.
// Each record is written with one write() and flushed to the disk
// (fdatasync) before the next point is reported, so a kill at any moment
// loses at most the points still running; a torn last line (a kill in
// the middle of a write) is dropped when the journal is opened again.
// Failed points are recorded like the others (the same point fails the
// same way again). A journal is held by one sweep at a time (flock).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "sim/batch/sweep.h"
#include "sim/io/files.h"

namespace ipmc {

// The identity of a sweep's points, 16 hex digits: FNV-1a (64 bit) over
// the table's columns and, for every point, its swept values, its
// resolved scenario (the base with the point's overrides, as TOML), its
// error, and the contents of the model file it runs. Editing a comment of
// the sweep file keeps it; changing any value a point runs with, or the
// model, changes it.
std::string SweepFingerprint(const SweepPlan& plan);

struct SweepJournalHeader {
  std::string program_version;  // of the program that created the journal
  std::string sweep;        // the sweep file, as it was given
  std::string fingerprint;  // SweepFingerprint
  int points = 0;           // in the whole sweep (all shards)
  std::vector<std::string> columns;
};

struct SweepJournalContents {
  SweepJournalHeader header;
  std::map<int, std::vector<std::string>> rows;  // by point index
};

// Reads a journal without taking it. Throws std::runtime_error
// "PATH:LINE: ..." if it is not one (a torn last line is not an error).
SweepJournalContents ReadSweepJournal(const std::string& path);

// The journal beside a table: "dir/shard_2.csv" -> "dir/shard_2.journal".
std::string JournalPathOf(const std::string& table_csv_path);

class SweepJournal {
 public:
  // Opens `path` for `plan`, creating it (and its directory) with its
  // header if it does not exist. Throws std::runtime_error (one line,
  // naming the path) if it records another sweep (a different
  // fingerprint), is not a journal, or another sweep holds it; nothing is
  // written then. A journal created by another program version is refused
  // too, unless `accept_other_version`.
  SweepJournal(const std::string& path, const SweepPlan& plan, bool accept_other_version = false);

  const std::string& path() const { return file_.path(); }
  // SweepFingerprint of the sweep it records.
  const std::string& fingerprint() const { return fingerprint_; }
  // The points recorded so far.
  const std::map<int, std::vector<std::string>>& rows() const { return rows_; }
  // Appends a finished point's row (row[0] is its index) and returns once
  // it is on the disk. Throws std::runtime_error naming the path.
  void Record(const std::vector<std::string>& row);
  // Closes and deletes the journal (a sweep with nothing worth resuming).
  void Remove();

 private:
  JournalFile file_;
  std::string fingerprint_;  // of the sweep it records (each record's check)
  std::map<int, std::vector<std::string>> rows_;
};

// A row's checksum: SHA-256 over the sweep's fingerprint, the point's
// index and every cell of its row, each with its length first. The
// journal's records and the table's JSON ("row_checks") carry it, so that
// a row edited by hand, copied from another sweep or given another status
// no longer matches.
std::string SweepRowCheck(const std::string& fingerprint, int point,
                          const std::vector<std::string>& row);

// A shard's points, and how many of them a journal holds.
struct ShardRecord {
  int points = 0;
  int recorded = 0;
};
ShardRecord CountRecorded(const SweepPlan& plan, const SweepShard& shard,
                          const SweepJournal& journal);

struct JournaledSweep {
  SweepTable table;     // the shard's rows that exist, by point index
  int shard_points = 0;  // points in the shard
  int resumed = 0;       // of them, recorded before this run
  bool Complete() const { return static_cast<int>(table.rows.size()) == shard_points; }
};

// RunSweep of options' shard, without the points the journal holds, each
// point recorded in the journal as it finishes (before
// options.on_point_done sees it). If options.stop_requested stops it,
// the table holds the points finished so far (Complete() is false).
JournaledSweep RunJournaledSweep(const SweepPlan& plan, SweepOptions options,
                                 SweepJournal* journal);

}  // namespace ipmc
