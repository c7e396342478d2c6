#include "sim/batch/sweep_status.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>

#include "sim/batch/journal.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

constexpr char kShardsDir[] = "shards";
constexpr char kJournalExtension[] = ".journal";
constexpr char kOk[] = "ok";

std::vector<std::string> JournalsIn(const fs::path& dir) {
  std::vector<std::string> journals;
  std::error_code error;
  if (!fs::is_directory(dir, error)) return journals;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, error)) {
    if (entry.is_regular_file(error) && entry.path().extension() == kJournalExtension) {
      journals.push_back(entry.path().string());
    }
  }
  return journals;
}

// The sweep of the first journal; every other must have its fingerprint.
void CheckSameSweep(const SweepJournalHeader& first, const std::string& first_path,
                    const SweepJournalHeader& other, const std::string& other_path) {
  if (other.fingerprint != first.fingerprint) {
    throw std::runtime_error(other_path + ": records another sweep than " + first_path + " (" +
                             other.sweep + ", fingerprint " + other.fingerprint + " vs " +
                             first.sweep + ", " + first.fingerprint + ")");
  }
}

size_t StatusColumn(const std::vector<std::string>& columns) {
  return static_cast<size_t>(std::find(columns.begin(), columns.end(), "status") -
                             columns.begin());
}

}  // namespace

SweepStatus ReadSweepStatus(const std::string& dir) {
  SweepStatus status;
  status.journals = JournalsIn(dir);
  const std::vector<std::string> shards = JournalsIn(fs::path(dir) / kShardsDir);
  status.journals.insert(status.journals.end(), shards.begin(), shards.end());
  std::sort(status.journals.begin(), status.journals.end());
  if (status.journals.empty()) {
    throw std::runtime_error(dir + ": no sweep journal here (sweep --slurm DIR keeps them in "
                                   "DIR/shards, sweep --out DIR/PREFIX in DIR)");
  }
  std::map<int, std::vector<std::string>> rows;
  std::optional<SweepJournalHeader> first;
  for (const std::string& path : status.journals) {
    SweepJournalContents contents = ReadSweepJournal(path);
    if (first) {
      CheckSameSweep(*first, status.journals.front(), contents.header, path);
    } else {
      first = contents.header;
    }
    rows.merge(contents.rows);
  }
  status.sweep = first->sweep;
  status.points = first->points;
  const size_t column = StatusColumn(first->columns);
  for (int point = 0; point < status.points; ++point) {
    const auto it = rows.find(point);
    if (it == rows.end()) {
      status.missing.push_back(point);
    } else if (it->second[column] == kOk) {
      status.done.push_back(point);
    } else {
      status.failed.emplace_back(point, it->second[column + 1]);
    }
  }
  return status;
}

std::string PointRanges(const std::vector<int>& points) {
  std::string text;
  for (size_t i = 0; i < points.size();) {
    size_t j = i;
    while (j + 1 < points.size() && points[j + 1] == points[j] + 1) ++j;
    if (!text.empty()) text += ", ";
    text += std::to_string(points[i]);
    if (j > i) text += "-" + std::to_string(points[j]);
    i = j + 1;
  }
  return text;
}

PartialMerge MergeAvailableTables(const std::vector<std::string>& csv_paths) {
  PartialMerge merge;
  std::vector<SweepTable> tables;
  std::vector<std::string> sources;
  std::optional<std::pair<SweepJournalHeader, std::string>> first_journal;
  for (const std::string& csv : csv_paths) {
    const std::string journal_path = JournalPathOf(csv);
    std::optional<SweepJournalContents> journal;
    std::error_code error;
    if (fs::exists(journal_path, error)) {
      journal = ReadSweepJournal(journal_path);
      if (first_journal) {
        CheckSameSweep(first_journal->first, first_journal->second, journal->header,
                       journal_path);
      } else {
        first_journal.emplace(journal->header, journal_path);
      }
      merge.points = std::max(merge.points, journal->header.points);
    }
    if (fs::exists(csv, error)) {
      tables.push_back(LoadSweepTableCsv(csv));
      sources.push_back(csv);
    } else if (journal) {
      SweepTable recorded;
      recorded.columns = journal->header.columns;
      recorded.fingerprint = journal->header.fingerprint;  // its records were checked
      for (auto& [point, row] : journal->rows) recorded.rows.push_back(std::move(row));
      merge.notes.push_back(csv + ": not written; " + std::to_string(recorded.rows.size()) +
                            " points from " + journal_path);
      tables.push_back(std::move(recorded));
      sources.push_back(journal_path);
    } else {
      merge.notes.push_back(csv + ": does not exist");
    }
  }
  if (tables.empty()) throw std::runtime_error("merge: none of the tables exists");
  merge.table = MergeSweepTables(tables, sources, /*allow_missing=*/true);
  std::vector<bool> present;
  for (const std::vector<std::string>& row : merge.table.rows) {
    const size_t index = std::stoul(row[0]);
    if (index >= present.size()) present.resize(index + 1, false);
    present[index] = true;
  }
  merge.points = std::max(merge.points, static_cast<int>(present.size()));
  present.resize(merge.points, false);
  for (int point = 0; point < merge.points; ++point) {
    if (!present[point]) merge.missing.push_back(point);
  }
  return merge;
}

}  // namespace ipmc
