// The journal of an optimisation (DIR/optimize.journal): lines of JSON,
// appended and never rewritten, each written with one write() and flushed
// to the disk (fdatasync) before the evaluation is reported.
//   {"ipmc_swim_optimize_journal": 2, "fingerprint": "...", "columns": [...]}   the header
//   {"x": ["0x1.b0a3d70a3d70ap+3", ...], "cells": ["ok", "", "0.31", ...], "check": "..."}
// x is the design's values as hex floats (bit for bit), cells the sweep
// row's cells after the point index (status, error, the metrics), check
// the SHA-256 of the fingerprint, x and cells: a record that fails it
// (edited by hand, or copied from another optimisation) is refused. A torn
// last line (a kill in the middle of a write) is cut off on opening. One
// optimisation holds it at a time (flock).
#pragma once

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "sim/io/files.h"

namespace ipmc {

// A journal's runs: the cells of each design, by HexKey.
using JournalRecords = std::map<std::string, std::vector<std::string>>;

// "0x1.b0a3d70a3d70ap+3,0x1.4p+3": the values bit for bit.
std::string HexKey(const std::vector<double>& x);

class OptimizeJournal {
 public:
  // Opens (or creates, with its header) the journal at `path`. Throws
  // std::runtime_error naming the path if it records another problem
  // (another fingerprint), is not a journal, or is held by another run.
  OptimizeJournal(const std::string& path, const std::string& fingerprint,
                  const std::vector<std::string>& columns);

  // The recorded cells of the design x, if any. Thread-safe.
  std::optional<std::vector<std::string>> Find(const std::vector<double>& x) const;
  // Appends a run; returns once it is on the disk. Thread-safe.
  void Record(const std::vector<double>& x, const std::vector<std::string>& cells);
  size_t size() const;

 private:
  JournalFile file_;
  std::string fingerprint_;
  mutable std::mutex mutex_;
  JournalRecords records_;
};

// The runs of the journal at `path`, read without holding it (another
// optimisation may be appending): none if there is no file. Throws
// std::runtime_error naming the path as the constructor does, and for a
// symbolic link or anything but a regular file.
JournalRecords ReadOptimizeJournal(const std::string& path, const std::string& fingerprint,
                                   const std::vector<std::string>& columns);

}  // namespace ipmc
