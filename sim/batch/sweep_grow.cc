#include "sim/batch/sweep_grow.h"

#include <filesystem>
#include <exception>
#include <optional>
#include <utility>

#include "sim/batch/journal.h"
#include "sim/batch/sweep_table.h"
#include "sim/core/data_paths.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {
namespace {

// A point's resolved inputs: its swept values, resolved scenario and model.
std::string InputsKey(const std::vector<std::string>& values, const PointProvenance& provenance) {
  std::string key;
  for (const std::string& value : values) key += std::to_string(value.size()) + ":" + value;
  return key + "|" + provenance.resolved_scenario + "|" + provenance.model_sha256;
}

// The earlier table at PREFIX if it is the complete table of the sweep
// that PREFIX.journal records, made by this program with `columns`.
std::optional<SweepTable> EarlierTable(const std::string& prefix,
                                       const std::vector<std::string>& columns,
                                       const std::string& fingerprint) {
  std::error_code error;
  const std::string journal_path = prefix + ".journal";
  if (!std::filesystem::is_regular_file(prefix + ".csv", error) ||
      !std::filesystem::is_regular_file(prefix + ".json", error) ||
      !std::filesystem::is_regular_file(journal_path, error)) {
    return std::nullopt;
  }
  const SweepJournalContents journal = ReadSweepJournal(journal_path);
  const SweepJournalHeader& header = journal.header;
  if (header.fingerprint == fingerprint || header.program_version != ProgramVersion() ||
      header.columns != columns) {
    return std::nullopt;
  }
  SweepTable table = LoadSweepTableCsv(prefix + ".csv");
  if (table.columns != columns || table.program_version != ProgramVersion() ||
      table.rows.size() != journal.rows.size()) {
    return std::nullopt;
  }
  for (const std::vector<std::string>& row : table.rows) {
    const auto recorded = journal.rows.find(std::stoi(row.at(0)));
    if (recorded == journal.rows.end() || recorded->second != row) return std::nullopt;
  }
  return table;
}

}  // namespace

std::map<int, std::vector<std::string>> ReusableSweepRows(const SweepPlan& plan,
                                                          const SweepShard& shard,
                                                          const std::string& prefix) {
  std::map<int, std::vector<std::string>> reused;
  std::error_code error;
  // Nothing to reuse without an earlier table: decided before any work,
  // so that a new sweep takes its journal (its lock) at once.
  if (prefix.empty() || plan.gait || !std::filesystem::is_regular_file(prefix + ".csv", error)) {
    return reused;
  }
  std::optional<SweepTable> earlier;
  try {
    earlier = EarlierTable(prefix, SweepColumns(plan), SweepFingerprint(plan));
  } catch (const std::exception&) {  // not a table or journal of ours: nothing to reuse
    return reused;
  }
  if (!earlier) return reused;
  const size_t keys = plan.keys.size();
  std::map<std::string, const std::vector<std::string>*> rows;  // by InputsKey
  for (const std::vector<std::string>& row : earlier->rows) {
    const auto provenance = earlier->provenance.find(std::stoi(row.at(0)));
    if (provenance == earlier->provenance.end() || row.size() <= keys) continue;
    const std::vector<std::string> values(row.begin() + 1, row.begin() + 1 + keys);
    rows.emplace(InputsKey(values, provenance->second), &row);
  }
  for (const SweepPoint& point : plan.points) {
    if (point.index % shard.count != shard.index - 1 || !point.scenario) continue;
    const PointProvenance provenance = {ResolvedScenarioToml(*point.scenario),
                                        ScenarioModelSha256(*point.scenario)};
    const auto match = rows.find(InputsKey(point.values, provenance));
    if (match == rows.end()) continue;
    std::vector<std::string> row = *match->second;
    row[0] = std::to_string(point.index);
    reused.emplace(point.index, std::move(row));
  }
  return reused;
}

}  // namespace ipmc
