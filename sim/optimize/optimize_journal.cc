#include "sim/optimize/optimize_journal.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "sim/base/error.h"
#include "sim/core/sha256.h"
#include "sim/io/files.h"

namespace ipmc {
namespace {

constexpr char kFormat[] = "ipmc_swim_optimize_journal";
// Format 2 added a checksum ("check") to every record.
constexpr int kFormatVersion = 2;

std::string Hex(double value) {
  char text[64];
  std::snprintf(text, sizeof(text), "%a", value);
  return text;
}

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw std::runtime_error(path + ": " + message);
}

nlohmann::json JournalHeader(const std::string& fingerprint,
                             const std::vector<std::string>& columns) {
  return {{kFormat, kFormatVersion}, {"fingerprint", fingerprint}, {"columns", columns}};
}

// A record's checksum: SHA-256 over the optimisation's fingerprint (its
// base scenario, [set] and design keys), the design's hex values and every
// cell, each with its length first. A record edited by hand or copied from
// another optimisation no longer matches.
std::string RecordCheck(const std::string& fingerprint, const std::vector<std::string>& x,
                        const std::vector<std::string>& cells) {
  std::vector<std::string> fields = {fingerprint, std::to_string(x.size())};
  fields.insert(fields.end(), x.begin(), x.end());
  fields.insert(fields.end(), cells.begin(), cells.end());
  return Sha256OfFields(fields);
}

// Checks the header line (line 1) of the journal at `path`.
void CheckHeader(const std::string& path, const nlohmann::json& record,
                 const nlohmann::json& header) {
  if (!record.is_object() || !record.contains(kFormat)) Fail(path, "not an optimisation journal");
  if (record[kFormat] != kFormatVersion) {
    Fail(path, "an optimisation journal of format " + record[kFormat].dump() +
                   ", this program reads format " + std::to_string(kFormatVersion) +
                   "; remove it to start over, or choose another out");
  }
  if (record.value("fingerprint", "") != header["fingerprint"] ||
      record.value("columns", nlohmann::json()) != header["columns"]) {
    Fail(path, "records another optimisation (its base scenario, [set] or design keys "
               "differ); use another --out");
  }
}

// One record line (not the header): its design's key and its cells.
std::pair<std::string, std::vector<std::string>> ParseRecord(const std::string& where,
                                                             const nlohmann::json& record,
                                                             const std::string& fingerprint,
                                                             size_t columns) {
  std::vector<std::string> x, cells;
  std::string check;
  try {
    x = record.at("x").get<std::vector<std::string>>();
    cells = record.at("cells").get<std::vector<std::string>>();
    check = record.at("check").get<std::string>();
  } catch (const nlohmann::json::exception&) {
    Fail(where, "not a journal record");
  }
  if (cells.size() != columns) Fail(where, "not a journal record");
  if (check != RecordCheck(fingerprint, x, cells)) {
    Fail(where, "the record fails its checksum (edited, or not written by this optimisation); "
                "delete that line to run the design again, or remove the journal");
  }
  std::string key;
  for (const std::string& value : x) key += (key.empty() ? "" : ",") + value;
  return {key, cells};
}

// The records of a journal's text (the header checked; a torn last line
// dropped).
JournalRecords ParseJournal(const std::string& path, const std::string& text,
                            const std::string& fingerprint,
                            const std::vector<std::string>& columns) {
  const nlohmann::json header = JournalHeader(fingerprint, columns);
  JournalRecords records;
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  size_t consumed = 0;
  while (std::getline(lines, line)) {
    ++number;
    consumed += line.size() + 1;
    if (consumed > text.size()) break;  // a torn last line
    const nlohmann::json record = nlohmann::json::parse(line, nullptr, false);
    if (number == 1) {
      CheckHeader(path, record, header);
      continue;
    }
    if (!record.is_object()) Fail(path + ":" + std::to_string(number), "not a journal record");
    auto [key, cells] =
        ParseRecord(path + ":" + std::to_string(number), record, fingerprint, columns.size());
    records[key] = std::move(cells);
  }
  return records;
}

}  // namespace

std::string HexKey(const std::vector<double>& x) {
  std::string key;
  for (double value : x) key += (key.empty() ? "" : ",") + Hex(value);
  return key;
}

OptimizeJournal::OptimizeJournal(const std::string& path, const std::string& fingerprint,
                                 const std::vector<std::string>& columns)
    : file_(path, "in use by another optimisation"), fingerprint_(fingerprint) {
  const std::string text = file_.Read();
  if (text.find('\n') == std::string::npos) {
    // New, or created by a run killed before its header was whole.
    try {
      file_.Reset(JournalHeader(fingerprint, columns).dump() + "\n");
    } catch (...) {
      if (text.empty()) file_.Discard();  // a failed start leaves nothing behind
      throw;
    }
    return;
  }
  records_ = ParseJournal(path, text, fingerprint, columns);
  // A torn last record (a kill in the middle of a write) is dropped, so
  // that the next record starts a line of its own.
  const size_t complete_size = text.rfind('\n') + 1;
  if (complete_size < text.size()) file_.Truncate(complete_size);
}

std::optional<std::vector<std::string>> OptimizeJournal::Find(const std::vector<double>& x) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = records_.find(HexKey(x));
  if (it == records_.end()) return std::nullopt;
  return it->second;
}

void OptimizeJournal::Record(const std::vector<double>& x, const std::vector<std::string>& cells) {
  nlohmann::json hex = nlohmann::json::array();
  for (double value : x) hex.push_back(Hex(value));
  const std::string check = RecordCheck(fingerprint_, hex.get<std::vector<std::string>>(), cells);
  const std::string line =
      nlohmann::json({{"x", hex}, {"cells", cells}, {"check", check}}).dump() + "\n";
  std::lock_guard<std::mutex> lock(mutex_);
  file_.Append(line);
  records_[HexKey(x)] = cells;
}

JournalRecords ReadOptimizeJournal(const std::string& path, const std::string& fingerprint,
                                   const std::vector<std::string>& columns) {
  const std::optional<std::string> text = ReadJournalText(path, "optimisation journal");
  if (!text) return {};
  return ParseJournal(path, *text, fingerprint, columns);
}

size_t OptimizeJournal::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return records_.size();
}

}  // namespace ipmc
