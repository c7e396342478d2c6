// Sweep tables: their columns, CSV and JSON forms, reading them back, and
// merging the tables of a sweep's shards.
#include "sim/batch/sweep_table.h"

#include "sim/batch/journal.h"
#include "sim/batch/sweep_gait.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"
#include "sim/io/result_files.h"
#include "sim/runs/run_warnings.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

// The status column of a table, checked.
size_t StatusColumn(const std::vector<std::string>& names, const std::string& source) {
  const auto status = std::find(names.begin(), names.end(), columns::kStatus);
  if (names.empty() || names.front() != columns::kPoint || status == names.end() ||
      status + 1 == names.end() || *(status + 1) != columns::kError) {
    throw InputError(InputProblem::kSyntax, {source, 1}, "",
                     "not a sweep table (expected columns point, ..., status, error, ...)");
  }
  return static_cast<size_t>(status - names.begin());
}

// A point index: a whole number >= 0 without a sign.
std::optional<long> PointIndex(const std::string& text) {
  if (text.empty() || text[0] == '-' || text[0] == '+') return std::nullopt;
  return ParseInteger(text);
}

nlohmann::ordered_json NumberJson(const std::string& text) {
  const std::optional<double> value = ParseDouble(text);
  if (!value || !std::isfinite(*value)) return nullptr;
  return *value;
}

nlohmann::ordered_json SweptValueJson(const std::string& text) {
  if (text.empty()) return nullptr;
  if (text == "true") return true;
  if (text == "false") return false;
  // The table writes numbers without a '+' (ValueText): one with it was a string.
  if (text[0] == '+') return text;
  if (const std::optional<long> integer = ParseInteger(text)) return *integer;
  const std::optional<double> value = ParseDouble(text);
  if (value && std::isfinite(*value)) return *value;
  if (text.front() == '[') {
    nlohmann::ordered_json array = nlohmann::ordered_json::parse(text, nullptr, false);
    if (!array.is_discarded()) return array;
  }
  return text;
}

}  // namespace

std::vector<std::string> SweepColumns(const SweepPlan& plan) {
  std::vector<std::string> names = {columns::kPoint};
  names.insert(names.end(), plan.keys.begin(), plan.keys.end());
  names.push_back(columns::kStatus);
  names.push_back(columns::kError);
  if (plan.gait) {  // a gait's metrics only (sim/batch/sweep_gait.h)
    names.insert(names.end(), kGaitResults.begin(), kGaitResults.end());
    return names;
  }
  for (int q = 1; q <= plan.links; ++q) {
    for (const char* result : columns::kLinkResults) {
      names.push_back(columns::LinkResult(q, result));
    }
  }
  names.insert(names.end(), std::begin(columns::kSwimResults), std::end(columns::kSwimResults));
  const std::vector<std::string> warnings = RunWarningColumns();
  names.insert(names.end(), warnings.begin(), warnings.end());
  return names;
}

std::string SweepTableCsv(const SweepTable& table) {
  CsvWriter csv;
  csv.Row(table.columns);
  for (const std::vector<std::string>& row : table.rows) csv.Row(row);
  return csv.Text();
}

nlohmann::ordered_json SweepTableJson(const SweepTable& table) {
  const size_t status = StatusColumn(table.columns, "sweep table");
  nlohmann::ordered_json points = nlohmann::ordered_json::array();
  for (const std::vector<std::string>& row : table.rows) {
    nlohmann::ordered_json point = nlohmann::ordered_json::object();
    for (size_t c = 0; c < table.columns.size() && c < row.size(); ++c) {
      nlohmann::ordered_json& cell = point[table.columns[c]];
      if (const std::optional<long> index = PointIndex(row[c]); c == 0 && index) {
        cell = *index;
      } else if (c == status || c == status + 1) {
        cell = row[c];
      } else if (c < status) {
        cell = SweptValueJson(row[c]);
      } else {
        cell = NumberJson(row[c]);
      }
    }
    points.push_back(std::move(point));
  }
  nlohmann::ordered_json json = {{"columns", table.columns}, {"points", std::move(points)}};
  if (!table.program_version.empty()) json["program_version"] = table.program_version;
  if (!table.provenance.empty()) {
    nlohmann::ordered_json provenance = nlohmann::ordered_json::array();
    for (const auto& [index, point] : table.provenance) {
      provenance.push_back({{"point", index},
                            {"resolved_scenario", point.resolved_scenario},
                            {"model_sha256", point.model_sha256}});
    }
    json["provenance"] = std::move(provenance);
  }
  if (!table.fingerprint.empty()) {
    json["fingerprint"] = table.fingerprint;
    nlohmann::ordered_json checks = nlohmann::ordered_json::array();
    for (const std::vector<std::string>& row : table.rows) {
      const std::optional<long> index = row.empty() ? std::nullopt : PointIndex(row[0]);
      if (!index) continue;
      const std::string check = SweepRowCheck(table.fingerprint, static_cast<int>(*index), row);
      checks.push_back({{"point", *index}, {"check", check}});
    }
    json["row_checks"] = std::move(checks);
  }
  return json;
}

SweepTable ParseSweepTableCsv(const std::string& csv_text, const std::string& source) {
  const CsvTable csv = CsvTable::Parse(csv_text, source);
  const size_t status = StatusColumn(csv.columns(), source);
  SweepTable table;
  table.columns = csv.columns();
  std::set<long> indices;
  for (size_t r = 0; r < csv.Rows(); ++r) {
    const std::vector<std::string>& row = csv.Row(r);
    const InputLocation where{source, static_cast<std::uint32_t>(csv.Line(r))};
    const std::optional<long> index = PointIndex(row[0]);
    if (!index) {
      throw InputError(InputProblem::kBadValue, where, columns::kPoint,
                       "point must be a whole number >= 0 (got '" + row[0] + "')",
                       "a whole number >= 0");
    }
    if (!indices.insert(*index).second) {
      throw InputError(InputProblem::kBadValue, where, columns::kPoint,
                       "point " + row[0] + " appears twice");
    }
    // The results after status and error: numbers in a point that ran.
    if (row[status] == columns::kStatusOk) {
      for (size_t c = status + 2; c < row.size(); ++c) {
        const std::optional<double> value = ParseDouble(row[c]);
        if (!value || !std::isfinite(*value)) {
          throw InputError(InputProblem::kBadValue, where, table.columns[c],
                           table.columns[c] + " must be a finite number (got '" + row[c] + "')",
                           "a finite number");
        }
      }
    }
    table.rows.push_back(row);
  }
  return table;
}

// The fingerprint of the table's JSON, with every CSV row checked against
// its row_checks: a number edited in the CSV (or the JSON's checks) is
// refused here, before any merge writes it.
void ReadSweepTableChecks(const nlohmann::ordered_json& json, const std::string& json_path,
                          SweepTable* table) {
  if (!json.contains("fingerprint")) return;
  const auto fail = [&](const std::string& key) {
    throw InputError(InputProblem::kSyntax, {json_path}, key,
                     "not a sweep table's JSON (" + key + " missing or malformed)");
  };
  if (!json["fingerprint"].is_string()) fail("fingerprint");
  if (!json.contains("row_checks") || !json["row_checks"].is_array()) fail("row_checks");
  std::map<long, std::string> checks;
  for (const nlohmann::ordered_json& entry : json["row_checks"]) {
    if (!entry.is_object() || !entry.contains("point") || !entry["point"].is_number_integer() ||
        !entry.contains("check") || !entry["check"].is_string()) {
      fail("row_checks");
    }
    checks[entry["point"].get<long>()] = entry["check"].get<std::string>();
  }
  table->fingerprint = json["fingerprint"].get<std::string>();
  for (const std::vector<std::string>& row : table->rows) {
    const long point = *PointIndex(row[0]);  // checked when parsed
    const auto it = checks.find(point);
    if (it == checks.end() ||
        it->second != SweepRowCheck(table->fingerprint, static_cast<int>(point), row)) {
      throw InputError(InputProblem::kBadValue, {json_path}, "row_checks",
                       "the row of point " + row[0] +
                           " in its CSV fails its checksum (edited, or not written by this "
                           "sweep); run the sweep again for a table to trust");
    }
  }
}

// The program version and provenance of the table's JSON (SweepTableJson).
void ReadSweepTableProvenance(const std::string& json_path, SweepTable* table) {
  const nlohmann::ordered_json json =
      nlohmann::ordered_json::parse(ReadTextFile(json_path, "sweep table"), nullptr, false);
  const auto fail = [&](const std::string& key) {
    throw InputError(InputProblem::kSyntax, {json_path}, key,
                     "not a sweep table's JSON (" + key + " missing or malformed)");
  };
  if (!json.is_object()) fail("columns");
  if (json.contains("program_version")) {
    if (!json["program_version"].is_string()) fail("program_version");
    table->program_version = json["program_version"].get<std::string>();
  }
  ReadSweepTableChecks(json, json_path, table);
  if (!json.contains("provenance")) return;
  if (!json["provenance"].is_array()) fail("provenance");
  for (const nlohmann::ordered_json& point : json["provenance"]) {
    if (!point.is_object() || !point.contains("point") || !point["point"].is_number_integer() ||
        !point.contains("resolved_scenario") || !point["resolved_scenario"].is_string() ||
        !point.contains("model_sha256") || !point["model_sha256"].is_string()) {
      fail("provenance");
    }
    table->provenance[point["point"].get<int>()] = {point["resolved_scenario"].get<std::string>(),
                                                    point["model_sha256"].get<std::string>()};
  }
}

SweepTable LoadSweepTableCsv(const std::string& path) {
  SweepTable table = ParseSweepTableCsv(ReadTextFile(path, "sweep table"), path);
  const fs::path json = fs::path(path).replace_extension(".json");
  std::error_code ignored;
  if (fs::path(path).extension() == ".csv" && fs::is_regular_file(json, ignored)) {
    ReadSweepTableProvenance(json.string(), &table);
  }
  return table;
}

namespace {

// The sweep fingerprint every table carries, "" if one carries none (its
// rows cannot be vouched for). Throws InputError naming the file if two
// differ: shards of two sweeps.
std::string CommonFingerprint(const std::vector<SweepTable>& tables,
                              const std::vector<std::string>& sources) {
  std::string common;
  size_t first = 0;
  bool every = true;
  for (size_t t = 0; t < tables.size(); ++t) {
    const std::string& fingerprint = tables[t].fingerprint;
    every = every && !fingerprint.empty();
    if (fingerprint.empty()) continue;
    if (common.empty()) {
      common = fingerprint;
      first = t;
    } else if (fingerprint != common) {
      throw InputError(InputProblem::kBadValue, {sources[t]}, "fingerprint",
                       "a shard of another sweep than " + sources[first] + " (fingerprint " +
                           fingerprint + " vs " + common + "); merge the shards of one sweep");
    }
  }
  return every ? common : std::string();
}

}  // namespace

SweepTable MergeSweepTables(const std::vector<SweepTable>& tables,
                            const std::vector<std::string>& sources, bool allow_missing) {
  if (tables.empty() || tables.size() != sources.size()) {
    throw std::invalid_argument("merge: needs one or more tables, each with its file name");
  }
  SweepTable merged;
  merged.columns = tables.front().columns;
  merged.fingerprint = CommonFingerprint(tables, sources);
  std::map<long, std::pair<const std::vector<std::string>*, size_t>> rows;  // -> row, table
  for (size_t t = 0; t < tables.size(); ++t) {
    const SweepTable& table = tables[t];
    StatusColumn(table.columns, sources[t]);
    if (table.columns != merged.columns) {
      size_t c = 0;
      while (c < table.columns.size() && c < merged.columns.size() &&
             table.columns[c] == merged.columns[c]) {
        ++c;
      }
      const std::string theirs = c < table.columns.size() ? "'" + table.columns[c] + "'" : "none";
      const std::string ours = c < merged.columns.size() ? "'" + merged.columns[c] + "'" : "none";
      throw InputError(InputProblem::kSyntax, {sources[t]}, "",
                       "columns differ from " + sources.front() + "'s (column " +
                           std::to_string(c + 1) + ": " + theirs + " vs " + ours + ")");
    }
    if (!table.program_version.empty()) {
      if (!merged.program_version.empty() && merged.program_version != table.program_version) {
        throw InputError(InputProblem::kBadValue, {sources[t]}, "program_version",
                         "made by ipmc-swim " + table.program_version + ", the tables before by " +
                             merged.program_version + " (merge tables of one program)");
      }
      merged.program_version = table.program_version;
    }
    for (const std::vector<std::string>& row : table.rows) {
      const std::optional<long> index = row.empty() ? std::nullopt : PointIndex(row[0]);
      if (!index) {
        throw InputError(InputProblem::kMissing, {sources[t]}, columns::kPoint,
                         "a row without a point index");
      }
      const auto [it, added] = rows.emplace(*index, std::make_pair(&row, t));
      const int point = static_cast<int>(*index);
      if (added && table.provenance.count(point) > 0) {
        merged.provenance[point] = table.provenance.at(point);
      }
      if (!added) {
        throw InputError(InputProblem::kBadValue, {sources[t]}, columns::kPoint,
                         "point " + row[0] + " is also in " + sources[it->second.second]);
      }
    }
  }
  long expected = 0;
  for (const auto& [index, row] : rows) {
    if (index != expected && !allow_missing) {
      std::string files;
      for (const std::string& source : sources) files += (files.empty() ? "" : ", ") + source;
      throw std::runtime_error("merge: point " + std::to_string(expected) +
                               " is missing (in none of " + files + "; they hold points up to " +
                               std::to_string(rows.rbegin()->first) + ")");
    }
    merged.rows.push_back(*row.first);
    ++expected;
  }
  return merged;
}

void CheckTablePrefix(const std::string& who, const std::string& option,
                      const std::string& prefix) {
  std::error_code error;
  if (prefix.empty() || prefix.back() == '/' || std::filesystem::is_directory(prefix, error)) {
    throw FieldError(who + ": " + option + " '" + prefix +
                         "' must name the table's files (PREFIX gives PREFIX.csv and "
                         "PREFIX.json), not a directory: add a name, e.g. " +
                         (prefix.empty() ? std::string("out/") : prefix +
                                                                  (prefix.back() == '/' ? "" : "/")) +
                         "table",
                     option, "a file name prefix");
  }
  // Its longest file is PREFIX.journal; the place and the names must take it.
  RequireWritableParent(prefix, ".journal");
}

nlohmann::ordered_json SweepResultTree(const SweepTable& table) {
  const nlohmann::ordered_json json = SweepTableJson(table);
  nlohmann::ordered_json tree;
  tree["table"] = json["points"];
  nlohmann::ordered_json points = nlohmann::ordered_json::object();
  for (const nlohmann::ordered_json& row : json["points"]) {
    points["point_" + std::to_string(row[columns::kPoint].get<long>())] = row;
  }
  if (json.contains("provenance")) {
    for (const nlohmann::ordered_json& source : json["provenance"]) {
      nlohmann::ordered_json& point =
          points["point_" + std::to_string(source[columns::kPoint].get<long>())];
      for (const auto& [key, value] : source.items()) {
        if (key != columns::kPoint) point[key] = value;
      }
    }
  }
  tree["points"] = points;
  if (json.contains("program_version")) tree["program_version"] = json["program_version"];
  return tree;
}

void WriteSweepTable(const std::string& prefix, const SweepTable& table,
                     const RunFileFormats& formats) {
  EnsureParentDirectory(prefix);
  const std::string json = SweepTableJson(table).dump(2) + "\n";
  std::vector<std::pair<std::string, std::string>> files;
  std::vector<std::string> stale;
  if (formats.mat || formats.hdf5) {
    const nlohmann::ordered_json tree = SweepResultTree(table);
    if (formats.mat) files.emplace_back(prefix + ".mat", MatFileBytes("sweep", tree));
    if (formats.hdf5) files.emplace_back(prefix + ".h5", Hdf5FileBytes(tree));
  }
  if (!formats.mat) stale.push_back(prefix + ".mat");
  if (!formats.hdf5) stale.push_back(prefix + ".h5");
  files.emplace_back(prefix + ".csv", SweepTableCsv(table));
  files.emplace_back(prefix + ".json", json);
  WriteFilesTogether(files, stale);
}

}  // namespace ipmc
